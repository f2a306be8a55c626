//! The bulky numeric arrays of a case file (orbit, force history, spectrum, Poincaré points)
//! as one base64 string of their `f64`s in little-endian bytes: exact (every bit, NaN and
//! −0 included), about half the bytes of decimal TOML and read back without parsing a number.
//! Used through `#[serde(with = …)]` on [`super::CaseRecord`]'s fields.

use crate::math::V2;
use base64::engine::general_purpose::STANDARD;
use base64::Engine as _;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serializer};

/// The base64 (standard alphabet, padded) of the little-endian bytes of `values`.
pub fn encode(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(f64::to_le_bytes).collect();
    STANDARD.encode(bytes)
}

/// The `f64`s of a string made by [`encode`], or why it is not one.
pub fn decode(s: &str) -> Result<Vec<f64>, String> {
    let bytes = STANDARD
        .decode(s)
        .map_err(|e| format!("not a packed array: {e}"))?;
    if !bytes.len().is_multiple_of(8) {
        return Err(format!(
            "packed array of {} bytes, not whole f64s",
            bytes.len()
        ));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect())
}

/// Pairs of the `f64`s of `s` (an even count).
fn pairs<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    let s = String::deserialize(d)?;
    let v = decode(&s).map_err(D::Error::custom)?;
    if !v.len().is_multiple_of(2) {
        return Err(D::Error::custom("packed pairs of an odd count of numbers"));
    }
    Ok(v.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
}

/// `Vec<V2>` as a packed string.
pub mod points {
    use super::*;

    /// Serializes the points as one packed string.
    pub fn serialize<S: Serializer>(v: &[V2], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&encode(v.iter().flatten().copied()))
    }

    /// Reads the points of a packed string.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<V2>, D::Error> {
        pairs(d)
    }
}

/// `Vec<(f64, f64)>` as a packed string.
pub mod tuples {
    use super::*;

    /// Serializes the pairs as one packed string.
    pub fn serialize<S: Serializer>(v: &[(f64, f64)], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&encode(v.iter().flat_map(|&(a, b)| [a, b])))
    }

    /// Reads the pairs of a packed string.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<(f64, f64)>, D::Error> {
        Ok(pairs(d)?.into_iter().map(|[a, b]| (a, b)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_arrays_round_trip_every_bit() {
        let special = [
            0.0,
            -0.0,
            1.5,
            f64::NAN,
            -f64::INFINITY,
            f64::MIN_POSITIVE,
            1e-310,
        ];
        for n in 0..special.len() {
            let v = &special[..n];
            let s = encode(v.iter().copied());
            let back = decode(&s).unwrap();
            assert_eq!(back.len(), n);
            for (a, b) in v.iter().zip(&back) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        }
        // 8 bytes are 12 characters with one padding character.
        assert_eq!(encode([1.0].into_iter()).len(), 12);
        for bad in ["A", "AAA=AAAA", "AA==", "AAAA", "A*AA", "===="] {
            assert!(decode(bad).is_err(), "{bad}");
        }
    }
}
