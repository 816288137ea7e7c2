//! File names from body names: a body may be called `tetra000/strut0` (a group and its part),
//! which as a file name would point into a folder that does not exist.

use std::collections::HashMap;

/// `name` with every character other than ASCII letters, digits, `.`, `-` and `_` replaced by
/// `_`, so that it names one file in the output folder (`tetra000/strut0` → `tetra000_strut0`).
pub fn file_stem(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') { c } else { '_' }).collect()
}

/// Refuses names that would share a file after [`file_stem`] (compared without case, as on
/// case-insensitive file systems): one body's files would silently overwrite the other's.
pub fn check_distinct_stems<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<(), String> {
    let mut seen: HashMap<String, &str> = HashMap::new();
    for name in names {
        let key = file_stem(name).to_lowercase();
        if let Some(first) = seen.insert(key, name) {
            return Err(format!(
                "bodies \"{first}\" and \"{name}\" would both be written as \"{}_*\" files; rename one of them",
                file_stem(name)
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{check_distinct_stems, file_stem};

    #[test]
    fn separators_and_odd_characters_become_underscores() {
        assert_eq!(file_stem("tetra000/strut0"), "tetra000_strut0");
        assert_eq!(file_stem(r"a\b:c d"), "a_b_c_d");
        assert_eq!(file_stem("plank-2.left_end"), "plank-2.left_end");
    }

    #[test]
    fn names_that_share_a_file_are_refused() {
        assert!(check_distinct_stems(["a/b", "a-b", "A.b"]).is_ok());
        let message = check_distinct_stems(["a/b", "c", "a_b"]).unwrap_err();
        assert!(message.contains("\"a/b\" and \"a_b\""), "{message}");
        assert!(check_distinct_stems(["Door", "door"]).is_err(), "case-insensitive file systems");
    }
}
