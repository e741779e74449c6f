//! The one stable hash of the crate: cache keys (light sets, sweep references), checksums
//! of cached data, and the content hash of golden images.
//!
//! Design rule: every key or checksum that is written to disk or compared across runs goes
//! through [`StableHasher`], never `std::hash::DefaultHasher` (whose output may change
//! between Rust releases and runs). The algorithm is XXH3-64 (the `xxhash-rust` crate, a
//! pure-Rust port of Collet's xxHash 0.8; XXH3's output has been frozen since xxHash 0.8.0,
//! so it is the same on every platform, release and run). It is not a cryptographic hash:
//! it guards against stale and damaged entries, not against an adversary who writes the
//! cache directory.
//!
//! Stored hashes carry their algorithm ([`tagged`], `"xxh3-64:<16 hex digits>"`), so a hash
//! written by an older algorithm is never compared as if it were this one's. Changing the
//! algorithm means changing [`ALGORITHM`] and bumping each cache's key tag, so old entries
//! are refused rather than misread.

use xxhash_rust::xxh3::Xxh3Default;

/// Name of the algorithm, the prefix of [`tagged`] strings.
pub const ALGORITHM: &str = "xxh3-64";

/// Streaming XXH3-64 with seed 0: feeding bytes in pieces gives the hash of their
/// concatenation.
#[derive(Clone, Default)]
pub struct StableHasher(Xxh3Default);

impl std::fmt::Debug for StableHasher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "StableHasher({})", tagged(self.finish()))
    }
}

impl StableHasher {
    /// A hasher that has been fed nothing.
    pub fn new() -> StableHasher {
        StableHasher::default()
    }
    /// Feeds bytes.
    pub fn write(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }
    /// Feeds a u64 as 8 little-endian bytes.
    pub fn write_u64(&mut self, v: u64) {
        self.write(&v.to_le_bytes());
    }
    /// Feeds a string prefixed by its length ([`Self::write_u64`]), so moving bytes between
    /// two adjacent strings changes the hash.
    pub fn write_str(&mut self, s: &str) {
        self.write_u64(s.len() as u64);
        self.write(s.as_bytes());
    }
    /// Feeds f32 values as their little-endian bits (`-0.0` and `0.0` differ; a NaN hashes
    /// its payload).
    pub fn write_f32s(&mut self, values: impl IntoIterator<Item = f32>) {
        for v in values {
            self.write(&v.to_le_bytes());
        }
    }
    /// The hash of everything fed so far (the hasher can go on being fed).
    pub fn finish(&self) -> u64 {
        self.0.digest()
    }
}

/// The stored form of a hash: `"<ALGORITHM>:<16 lower-case hex digits>"`.
pub fn tagged(hash: u64) -> String {
    format!("{ALGORITHM}:{hash:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// XXH3-64 (seed 0) of `bytes` through the streaming hasher.
    fn xxh3(bytes: &[u8]) -> u64 {
        let mut h = StableHasher::new();
        h.write(bytes);
        h.finish()
    }

    #[test]
    fn matches_the_reference_implementation() {
        // Expected values from the C reference implementation (xxHash 0.8, through the
        // Python `xxhash` package's xxh3_64_intdigest), not from this crate.
        assert_eq!(xxh3(b""), 0x2d06800538d394c2);
        assert_eq!(xxh3(b"a"), 0xe6c632b61e964e1f);
        assert_eq!(xxh3(b"abc"), 0x78af5f94892f3950);
        let long: Vec<u8> = (0..1280).map(|i| (i % 256) as u8).collect();
        assert_eq!(xxh3(&long), 0x4844b009e164352e);
    }

    #[test]
    fn pieces_hash_as_their_concatenation() {
        let long: Vec<u8> = (0..1280).map(|i| (i % 256) as u8).collect();
        let mut h = StableHasher::new();
        for chunk in long.chunks(7) {
            h.write(chunk);
        }
        assert_eq!(h.finish(), 0x4844b009e164352e);
    }

    #[test]
    fn strings_are_length_prefixed() {
        let pair = |a: &str, b: &str| {
            let mut h = StableHasher::new();
            h.write_str(a);
            h.write_str(b);
            h.finish()
        };
        assert_ne!(pair("ab", "c"), pair("a", "bc"));
        assert_eq!(pair("ab", "c"), pair("ab", "c"));
    }

    #[test]
    fn tagged_names_the_algorithm() {
        assert_eq!(tagged(0x2d06800538d394c2), "xxh3-64:2d06800538d394c2");
        assert_eq!(tagged(1), "xxh3-64:0000000000000001");
    }
}
