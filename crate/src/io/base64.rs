//! Minimal base64 decoding for glTF `data:` URIs (standard or URL-safe alphabet, padding
//! optional).

fn sextet(c: u8) -> Option<u32> {
    Some(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' | b'-' => 62,
        b'/' | b'_' => 63,
        _ => return None,
    } as u32)
}

/// Decoded size of `s` (an upper bound when `s` is invalid).
pub(super) fn decoded_len(s: &str) -> usize {
    let n = s.trim_end_matches('=').len();
    n / 4 * 3 + (n % 4 * 3) / 4
}

/// Decodes `s`, or returns the index of the first bad character.
pub(super) fn decode(s: &str) -> Result<Vec<u8>, usize> {
    let data = s.trim_end_matches('=').as_bytes();
    if data.len() % 4 == 1 {
        return Err(data.len());
    }
    let mut out = Vec::with_capacity(decoded_len(s));
    for (ci, chunk) in data.chunks(4).enumerate() {
        let mut acc = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            acc = (acc << 6) | sextet(c).ok_or(ci * 4 + k)?;
        }
        acc <<= 6 * (4 - chunk.len() as u32);
        let b = acc.to_be_bytes();
        out.extend_from_slice(&b[1..chunk.len()]);
    }
    Ok(out)
}

/// Encodes with the standard alphabet and padding (used by tests and seed generation).
pub fn encode(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let mut b = [0u8; 3];
        b[..chunk.len()].copy_from_slice(chunk);
        let v = u32::from_be_bytes([0, b[0], b[1], b[2]]);
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(A[(v >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        for n in 0..20 {
            let b: Vec<u8> = (0..n as u8).map(|i| i.wrapping_mul(37)).collect();
            let e = encode(&b);
            assert_eq!(decode(&e).unwrap(), b);
            assert_eq!(decoded_len(&e), b.len());
        }
        assert_eq!(decode("aGVsbG8=").unwrap(), b"hello");
        assert!(decode("a*==").is_err());
        assert!(decode("a").is_err());
    }
}
