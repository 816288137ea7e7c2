//! The text of a scene file and how to point into it: byte offsets to line and column, and the
//! table, key and body around an offset (for errors the TOML parser reports with a span only).

use std::ops::Range;
use std::path::Path;

use super::SceneError;

/// A scene file's text and name, for error messages.
pub(super) struct Source<'a> {
    /// The whole file.
    pub text: &'a str,
    /// Where it came from (printed in messages; relative mesh paths start from its folder).
    pub file: &'a Path,
}

/// What surrounds a byte offset: the table header above it, the key path down to it, and the
/// `[[body]]` it belongs to.
struct Context {
    /// Name in the last table header (`""` at top level, `body`, `body.dent`, `world`…).
    section: String,
    /// Byte offset of the last `[[body]]` header, when the section is a body or one of its
    /// sub-tables.
    body_header: Option<usize>,
    /// Keys from the statement's key to the value at the offset (inline tables nest).
    keys: Vec<String>,
    /// Byte offset of the statement's key (the first of `keys`).
    statement: Option<usize>,
}

impl<'a> Source<'a> {
    pub fn new(text: &'a str, file: &'a Path) -> Self {
        Self { text, file }
    }

    /// 1-based line and column (in characters) of byte `offset`.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = floor_char_boundary(self.text, offset);
        let before = &self.text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (before.matches('\n').count() + 1, before[line_start..].chars().count() + 1)
    }

    /// An [`SceneError::Invalid`] at byte range `span`.
    pub fn error_at(
        &self,
        span: Range<usize>,
        body: Option<&str>,
        field: &str,
        message: impl Into<String>,
    ) -> SceneError {
        let (line, column) = self.line_col(span.start);
        SceneError::Invalid {
            file: self.file.to_path_buf(),
            line,
            column,
            body: body.map(str::to_owned),
            field: field.to_owned(),
            message: message.into(),
        }
    }

    /// A TOML parse or deserialization error, with the field and body found around its span.
    pub fn toml_error(&self, error: &toml::de::Error) -> SceneError {
        let mut message = error.message().trim().to_owned();
        let Some(span) = error.span() else {
            return SceneError::Invalid {
                file: self.file.to_path_buf(),
                line: 0,
                column: 0,
                body: None,
                field: String::new(),
                message,
            };
        };
        // Errors about a whole table (a missing field) point at its header: read past it.
        let start = floor_char_boundary(self.text, span.start);
        let (before, after) = self.text.split_at(start);
        let at_header = after.starts_with('[') && before.rsplit('\n').next().is_some_and(|l| l.trim().is_empty());
        let header_end = at_header.then(|| after.find('\n').map_or(self.text.len(), |n| start + n));
        let context = self.context(header_end.unwrap_or(span.start));
        if let (Some(start), Some(key)) = (context.statement, context.keys.first()) {
            let (key_line, _) = self.line_col(start);
            if key_line < self.line_col(span.start).0 {
                message += &format!(" (in the value of `{key}` that starts on line {key_line})");
            }
        }
        let mut keys = context.keys;
        // Unknown fields are reported on the key itself.
        if let Some(key) = self.key_at(span.clone()) {
            keys.push(key);
        }
        let prefix = match context.section.as_str() {
            "" | "body" => String::new(),
            s => format!("{}.", s.strip_prefix("body.").unwrap_or(s)),
        };
        let field = if keys.is_empty() { prefix.trim_end_matches('.').to_owned() } else { prefix + &keys.join(".") };
        let body = context.body_header.and_then(|at| self.body_name(at));
        self.error_at(span, body.as_deref(), &field, message)
    }

    /// Byte offset of `key` written in table `[section]` (or at top level as `section.key` or in
    /// `section = { … }`), for errors found after parsing in settings kept without spans.
    pub fn find_key(&self, section: &str, key: &str) -> Option<usize> {
        let mut in_section = false;
        let mut offset = 0;
        for line in self.text.split_inclusive('\n') {
            let trimmed = line.trim_start();
            let indent = line.len() - trimmed.len();
            if trimmed.starts_with('[') {
                in_section = header_name(trimmed) == section;
            } else if in_section && key_of(trimmed) == Some(key) {
                return Some(offset + indent);
            } else if !in_section
                && let Some(k) = key_of(trimmed)
                && k.strip_prefix(section).and_then(|k| k.strip_prefix('.')).is_some_and(|k| k.trim() == key)
            {
                return Some(offset + indent);
            }
            offset += line.len();
        }
        None
    }

    /// Byte offset of the header `[section]`.
    pub fn find_header(&self, section: &str) -> Option<usize> {
        let mut offset = 0;
        for line in self.text.split_inclusive('\n') {
            let trimmed = line.trim_start();
            if trimmed.starts_with('[') && header_name(trimmed) == section {
                return Some(offset + line.len() - trimmed.len());
            }
            offset += line.len();
        }
        None
    }

    /// The whole key when `span` covers exactly a bare key followed by `=`.
    fn key_at(&self, span: Range<usize>) -> Option<String> {
        let text = self.text.get(span.clone())?;
        let is_key = !text.is_empty() && text.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
        let followed_by_equals = self.text[span.end..].trim_start_matches([' ', '\t']).starts_with('=');
        (is_key && followed_by_equals).then(|| text.to_owned())
    }

    /// The value of `name = "…"` in the `[[body]]` whose header starts at `header`.
    fn body_name(&self, header: usize) -> Option<String> {
        let mut lines = self.text[header..].lines();
        lines.next();
        for line in lines {
            let trimmed = line.trim_start();
            if trimmed.starts_with('[') {
                return None;
            }
            if key_of(trimmed) == Some("name") {
                let value = trimmed.split_once('=')?.1.trim();
                let quote = value.chars().next().filter(|c| *c == '"' || *c == '\'')?;
                return Some(value[1..].split(quote).next()?.to_owned());
            }
        }
        None
    }

    /// Scans the text up to `offset`: strings and comments skipped, headers, keys, inline tables
    /// and arrays followed.
    fn context(&self, offset: usize) -> Context {
        let bytes = self.text.as_bytes();
        let end = offset.min(bytes.len());
        let mut context = Context { section: String::new(), body_header: None, keys: Vec::new(), statement: None };
        let mut stack: Vec<String> = Vec::new();
        let mut pending: Option<String> = None;
        let mut arrays = 0usize;
        let mut statement_start = true;
        let mut i = 0;
        while i < end {
            match bytes[i] {
                b'#' => i = self.text[i..].find('\n').map_or(bytes.len(), |n| i + n) - 1,
                b'"' | b'\'' => match skip_string(bytes, i) {
                    Some(next) => i = next - 1,
                    None => break,
                },
                b'\n' if arrays == 0 && stack.is_empty() => {
                    statement_start = true;
                    pending = None;
                    context.statement = None;
                }
                b'[' if statement_start => {
                    let line_end = self.text[i..].find('\n').map_or(bytes.len(), |n| i + n);
                    context.section = header_name(&self.text[i..line_end]).to_owned();
                    let is_body = context.section == "body" && self.text[i..].starts_with("[[");
                    if is_body {
                        context.body_header = Some(i);
                    } else if !context.section.starts_with("body.") {
                        context.body_header = None;
                    }
                    stack.clear();
                    pending = None;
                    context.statement = None;
                    i = line_end - 1;
                }
                b'[' => arrays += 1,
                b']' => arrays = arrays.saturating_sub(1),
                b'{' => stack.extend(pending.take()),
                b'}' => pending = stack.pop(),
                b',' if arrays == 0 && !stack.is_empty() => pending = None,
                b'=' => {
                    pending = key_before(&self.text[..i]);
                    if stack.is_empty() && arrays == 0 {
                        let key_len = pending.as_ref().map_or(0, String::len);
                        context.statement = Some(self.text[..i].trim_end_matches([' ', '\t']).len() - key_len);
                    }
                }
                _ => {}
            }
            if bytes[i] != b'\n' && !bytes[i].is_ascii_whitespace() {
                statement_start = false;
            }
            i += 1;
        }
        context.keys = stack.into_iter().chain(pending).collect();
        context
    }
}

/// The index just past the string starting at `start` (basic or literal, single- or
/// multi-line), or `None` when it does not close.
fn skip_string(bytes: &[u8], start: usize) -> Option<usize> {
    let quote = bytes[start];
    let triple = bytes.get(start..start + 3) == Some(&[quote; 3][..]);
    let mut i = start + if triple { 3 } else { 1 };
    while i < bytes.len() {
        match bytes[i] {
            b'\\' if quote == b'"' => i += 1,
            b'\n' if !triple => return None,
            q if q == quote && (!triple || bytes.get(i..i + 3) == Some(&[quote; 3][..])) => {
                return Some(i + if triple { 3 } else { 1 });
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// The bare (possibly dotted) key that ends just before an `=` at the end of `text`.
fn key_before(text: &str) -> Option<String> {
    let trimmed = text.trim_end_matches([' ', '\t']);
    // The key starts after the last character that cannot be in a bare key (which may be
    // several bytes long: a key may follow any UTF-8 text).
    let start = trimmed
        .char_indices()
        .rev()
        .find(|&(_, c)| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
        .map_or(0, |(i, c)| i + c.len_utf8());
    let key = &trimmed[start..];
    (!key.is_empty()).then(|| key.to_owned())
}

/// `body.dent` for a header line `[ body.dent ]` or `[[body]]` (comments after it ignored).
fn header_name(line: &str) -> &str {
    let inner = line.trim_start().trim_start_matches('[');
    inner.split(']').next().unwrap_or("").trim()
}

/// The key of a `key = value` line (trimmed at the start), if it is one.
fn key_of(trimmed: &str) -> Option<&str> {
    let (key, _) = trimmed.split_once('=')?;
    let key = key.trim();
    (!key.is_empty() && key.bytes().all(|b| b.is_ascii_alphanumeric() || b"_-.".contains(&b))).then_some(key)
}

/// The largest char boundary ≤ `offset` (and ≤ the text's length).
fn floor_char_boundary(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}
