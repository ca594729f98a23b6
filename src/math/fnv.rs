//! FNV-1a, 64 bits (Fowler, Noll and Vo; the parameters of the IETF draft
//! draft-eastlake-fnv): a hash whose value is fixed by its definition, so files written by
//! one build or machine can be compared by another (std's `DefaultHasher` promises no such
//! stability across Rust versions).

const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// An FNV-1a 64 hash being fed bytes.
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a64(u64);

impl Default for Fnv1a64 {
    fn default() -> Self {
        Fnv1a64(OFFSET_BASIS)
    }
}

impl Fnv1a64 {
    /// Feed `bytes`: per byte, XOR it in, then multiply by the FNV prime.
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(PRIME);
        }
    }

    /// Feed a byte string with its length first, so ("ab", "c") and ("a", "bc") differ.
    pub fn write_field(&mut self, bytes: &[u8]) {
        self.write(&(bytes.len() as u64).to_le_bytes());
        self.write(bytes);
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::Fnv1a64;

    fn hash(s: &str) -> u64 {
        let mut h = Fnv1a64::default();
        h.write(s.as_bytes());
        h.finish()
    }

    /// The published FNV-1a 64 test vectors (draft-eastlake-fnv, section 8).
    #[test]
    fn matches_the_reference_vectors() {
        assert_eq!(hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(hash("a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(hash("foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn fields_are_delimited() {
        let mut a = Fnv1a64::default();
        a.write_field(b"ab");
        a.write_field(b"c");
        let mut b = Fnv1a64::default();
        b.write_field(b"a");
        b.write_field(b"bc");
        assert_ne!(a.finish(), b.finish());
    }
}
