//! The `.npy` output of a height field.

/// A `.npy` file (format version 1.0) holding `data` as a C-order float64 array of `shape`:
/// the magic string, a header dictionary padded with spaces to a multiple of 64 bytes, then the
/// little-endian values. `data.len()` must equal the product of `shape`.
pub fn npy_bytes(data: &[f64], shape: &[usize]) -> Vec<u8> {
    debug_assert_eq!(data.len(), shape.iter().product::<usize>());
    let dims = match shape {
        [d] => format!("({d},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {dims}, }}");
    // magic (6) + version (2) + header length (2) + header, ending in '\n', to a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + 8 * data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_bytes_have_a_valid_header_and_the_values() {
        let data: Vec<f64> = (0..6).map(|i| i as f64 * 0.5 - 1.0).collect();
        let b = npy_bytes(&data, &[3, 2]);
        assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
        let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hl) % 64, 0);
        let header = std::str::from_utf8(&b[10..10 + hl]).unwrap();
        assert!(header.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }"));
        assert!(header.ends_with('\n'));
        assert_eq!(b.len(), 10 + hl + 48);
        for (k, v) in data.iter().enumerate() {
            let at = 10 + hl + 8 * k;
            assert_eq!(f64::from_le_bytes(b[at..at + 8].try_into().unwrap()), *v);
        }
        let b1 = npy_bytes(&[1.0; 5], &[5]);
        let hl = u16::from_le_bytes([b1[8], b1[9]]) as usize;
        assert!(
            std::str::from_utf8(&b1[10..10 + hl])
                .unwrap()
                .contains("'shape': (5,)")
        );
    }
}
