//! Readers of the export formats for the tests: `.npy` v1.0 (little-endian float64, C order)
//! and stored zip archives (`.npz`), parsed independently of the exporter.

use std::collections::BTreeMap;

pub fn u16le(b: &[u8], at: usize) -> usize {
    u16::from_le_bytes([b[at], b[at + 1]]) as usize
}

pub fn u32le(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize
}

/// Parses a v1.0 `.npy` of little-endian float64 (C order): its shape and data.
pub fn parse_npy(b: &[u8]) -> (Vec<usize>, Vec<f64>) {
    assert_eq!(&b[..8], b"\x93NUMPY\x01\x00", "magic/version");
    let hl = u16le(b, 8);
    assert_eq!((10 + hl) % 64, 0, "header padded to 64 bytes");
    let dict = std::str::from_utf8(&b[10..10 + hl]).unwrap();
    assert!(dict.contains("'descr': '<f8'") && dict.contains("'fortran_order': False"));
    let shape = dict
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    let data: Vec<f64> = b[10 + hl..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(data.len(), shape.iter().product::<usize>(), "{dict}");
    (shape, data)
}

/// The entries of a zip through its central directory (stored entries, CRC checked).
pub fn parse_zip(b: &[u8]) -> BTreeMap<String, Vec<u8>> {
    let end = b.len() - 22;
    assert_eq!(u32le(b, end), 0x0605_4b50, "end of central directory");
    let count = u16le(b, end + 10);
    let mut at = u32le(b, end + 16);
    let mut out = BTreeMap::new();
    for _ in 0..count {
        assert_eq!(u32le(b, at), 0x0201_4b50, "central directory entry");
        assert_eq!(u16le(b, at + 10), 0, "stored");
        let crc = u32le(b, at + 16) as u32;
        let size = u32le(b, at + 20);
        assert_eq!(size, u32le(b, at + 24), "stored: sizes equal");
        let (nl, xl, cl) = (u16le(b, at + 28), u16le(b, at + 30), u16le(b, at + 32));
        let local = u32le(b, at + 42);
        let name = String::from_utf8(b[at + 46..at + 46 + nl].to_vec()).unwrap();
        assert_eq!(u32le(b, local), 0x0403_4b50, "local header of {name}");
        let data_at = local + 30 + u16le(b, local + 26) + u16le(b, local + 28);
        let data = b[data_at..data_at + size].to_vec();
        assert_eq!(crc32fast::hash(&data), crc, "CRC of {name}");
        out.insert(name, data);
        at += 46 + nl + xl + cl;
    }
    out
}
