//! Parsing of `X,Y,Z` vector arguments.

use dentbend::glam::Vec3;

/// Parses three comma-separated finite numbers, `X,Y,Z` (blanks around each are allowed), for
/// clap's `value_parser`.
pub fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three comma-separated numbers X,Y,Z, got {}", count(parts.len())));
    }
    let mut xyz = [0.0f32; 3];
    for (slot, part) in xyz.iter_mut().zip(&parts) {
        let value: f32 = part.parse().map_err(|_| format!("'{part}' is not a number"))?;
        if !value.is_finite() {
            return Err(format!("'{part}' is not a finite number"));
        }
        *slot = value;
    }
    Ok(Vec3::from_array(xyz))
}

fn count(n: usize) -> String {
    match n {
        1 => "1 value".to_owned(),
        n => format!("{n} values"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        assert_eq!(parse_vec3("1,2,3"), Ok(Vec3::new(1.0, 2.0, 3.0)));
        assert_eq!(parse_vec3(" -1.5 , 0,2e-1"), Ok(Vec3::new(-1.5, 0.0, 0.2)));
        for bad in ["1,2", "1,2,3,4", "a,b,c", "nan,0,1", "inf,0,0", "1,,2", ""] {
            assert!(parse_vec3(bad).is_err(), "{bad}");
        }
    }
}
