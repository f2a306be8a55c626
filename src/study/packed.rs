//! The bulky numeric arrays of a case file (orbit, force history, spectrum, Poincaré points)
//! as one base64 string of their `f64`s in little-endian bytes: exact (every bit, NaN and
//! −0 included), about half the bytes of decimal TOML and read back without parsing a number.
//! Used through `#[serde(with = …)]` on [`super::CaseRecord`]'s fields.

use crate::math::V2;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serializer};

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// The base64 (standard alphabet, padded) of the little-endian bytes of `values`.
pub fn encode(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(f64::to_le_bytes).collect();
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for (k, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if k <= c.len() {
                s.push(char::from(ALPHABET[((n >> shift) & 63) as usize]));
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// The `f64`s of a string made by [`encode`], or why it is not one.
pub fn decode(s: &str) -> Result<Vec<f64>, String> {
    let b = s.as_bytes();
    if !b.len().is_multiple_of(4) {
        return Err(format!(
            "packed array of {} characters, not a multiple of 4",
            b.len()
        ));
    }
    let mut bytes = Vec::with_capacity(b.len() / 4 * 3);
    for (i, q) in b.chunks(4).enumerate() {
        let last = i + 1 == b.len() / 4;
        let pad = q.iter().rev().take_while(|&&c| c == b'=').count();
        if pad > 2 || (pad > 0 && !last) {
            return Err("misplaced padding in a packed array".into());
        }
        let mut n = 0u32;
        for &c in &q[..4 - pad] {
            n = (n << 6)
                | sextet(c).ok_or_else(|| format!("{:?} in a packed array", char::from(c)))?;
        }
        n <<= 6 * pad as u32;
        bytes.extend_from_slice(&[(n >> 16) as u8, (n >> 8) as u8, n as u8][..3 - pad]);
    }
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

/// The value of one base64 character.
fn sextet(c: u8) -> Option<u32> {
    Some(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => return None,
    } as u32)
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
