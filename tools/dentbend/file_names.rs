//! File names from body names: a body may be called `tetra000/strut0` (a group and its part),
//! which as a file name would point into a folder that does not exist.

/// `name` with every character other than ASCII letters, digits, `.`, `-` and `_` replaced by
/// `_`, so that it names one file in the output folder (`tetra000/strut0` → `tetra000_strut0`).
pub fn file_stem(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') { c } else { '_' }).collect()
}

#[cfg(test)]
mod tests {
    use super::file_stem;

    #[test]
    fn separators_and_odd_characters_become_underscores() {
        assert_eq!(file_stem("tetra000/strut0"), "tetra000_strut0");
        assert_eq!(file_stem(r"a\b:c d"), "a_b_c_d");
        assert_eq!(file_stem("plank-2.left_end"), "plank-2.left_end");
    }
}
