//! The value types the scene file's tables share: `[x, y, z]` triples and scales, each read from
//! exactly three numbers (serde's arrays would ignore extra elements in TOML).

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};

/// An `[x, y, z]` array of exactly three numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Triple(pub [f32; 3]);

/// `scale = 2` or `scale = [1, 0.5, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Scale(pub [f32; 3]);

/// Reads exactly three numbers from `seq` (serde's arrays ignore extra elements in TOML).
fn three<'de, A: SeqAccess<'de>>(mut seq: A, expected: &dyn de::Expected) -> Result<[f32; 3], A::Error> {
    let mut out = [0.0f32; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        *slot = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, expected))?;
    }
    let mut count = 3;
    while seq.next_element::<IgnoredAny>()?.is_some() {
        count += 1;
    }
    if count > 3 {
        return Err(de::Error::invalid_length(count, expected));
    }
    Ok(out)
}

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TripleVisitor;
        impl<'de> Visitor<'de> for TripleVisitor {
            type Value = Triple;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an [x, y, z] array of three numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Triple, A::Error> {
                three(seq, &self).map(Triple)
            }
        }
        deserializer.deserialize_seq(TripleVisitor)
    }
}

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ScaleVisitor;
        impl<'de> Visitor<'de> for ScaleVisitor {
            type Value = Scale;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an [x, y, z] array of three numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Scale, A::Error> {
                three(seq, &self).map(Scale)
            }
        }
        deserializer.deserialize_any(ScaleVisitor)
    }
}
