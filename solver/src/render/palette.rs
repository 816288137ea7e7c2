//! Colours that tell bones apart in pictures: bone k, its sub-body and its level-set cells share
//! [`bone_colour`]`(k)`.

/// The first ten bone colours, linear RGB (a common ten-colour categorical palette: blue,
/// orange, green, red, purple, brown, pink, olive, cyan, grey).
const PALETTE: [[f32; 3]; 10] = [
    [0.014, 0.184, 0.456],
    [1.0, 0.212, 0.004],
    [0.025, 0.352, 0.025],
    [0.672, 0.02, 0.021],
    [0.296, 0.136, 0.509],
    [0.262, 0.093, 0.07],
    [0.768, 0.184, 0.539],
    [0.503, 0.509, 0.016],
    [0.009, 0.515, 0.624],
    [0.216, 0.216, 0.216],
];

/// Colour of bone `k`, linear RGB in [0, 1]: ten distinct colours, then hues a golden angle
/// apart (saturated, mid-bright) for bones added by splits.
pub fn bone_colour(k: usize) -> [f32; 3] {
    if let Some(&colour) = PALETTE.get(k) {
        return colour;
    }
    let hue = ((k - PALETTE.len()) as f32 * 0.381_966).fract() * 6.0;
    let ramp = |offset: f32| (((hue + offset) % 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0);
    [ramp(0.0), ramp(4.0), ramp(2.0)].map(|c| 0.05 + 0.6 * c)
}

/// `colour` mixed towards white by `amount` in [0, 1] (0: unchanged, 1: white), linear RGB.
pub(crate) fn lighten(colour: [f32; 3], amount: f32) -> [f32; 3] {
    colour.map(|c| c + (1.0 - c) * amount.clamp(0.0, 1.0))
}

/// `colour` scaled towards black by `amount` in [0, 1] (0: unchanged, 1: black), linear RGB.
pub(crate) fn darken(colour: [f32; 3], amount: f32) -> [f32; 3] {
    colour.map(|c| c * (1.0 - amount.clamp(0.0, 1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_are_distinct_and_in_range() {
        let colours: Vec<[f32; 3]> = (0..40).map(bone_colour).collect();
        for (i, a) in colours.iter().enumerate() {
            assert!(a.iter().all(|c| (0.0..=1.0).contains(c)), "bone {i}: {a:?}");
            for b in &colours[..i] {
                let d: f32 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
                assert!(d > 1e-3, "bone {i} repeats a colour: {a:?}");
            }
        }
    }
}
