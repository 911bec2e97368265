//! A tiny little-endian byte writer and reader for versioned, pointer-free model states.
//!
//! Every model serializes its whole state with [`ByteWriter`] and restores it with
//! [`ByteReader`]. The format is plain little-endian: `u32`/`u64`/`i32` as 4/8/4 bytes, `f64` as
//! its IEEE-754 bits (so NaN payloads and signed zeros survive bit-exactly), `bool` as one byte
//! (0 or 1), and strings, byte blobs and `f64` slices as a `u64` length followed by the items.
//!
//! Every read is bounds-checked and returns [`ModelError::BadState`] with a message that names
//! the field being read, its offset and what was found; nothing here panics on bad input.
//!
//! A model's bytes should start with [`ByteWriter::header`] (the model's tag and a format
//! version) so that a state from another model or a newer format is refused with a clear message.

use std::cell::RefCell;

use super::ModelError;

/// One field read by a [`ByteReader`] while [`trace_fields`] records (the adversarial harness
/// mutates each of them in turn: tests/python/adversarial.py).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldSpan {
    /// Offset of the field's first byte in the traced buffer.
    pub offset: usize,
    /// Length [bytes].
    pub len: usize,
    /// `magic`, `u8`, `bool`, `u32`, `i32`, `u64`, `f64`, `len` (a length prefix) or `str`.
    pub kind: &'static str,
    /// The reader's name for the field.
    pub what: String,
}

thread_local! {
    /// Fields read on this thread while [`trace_fields`] runs: (buffer start, spans).
    static TRACE: RefCell<Option<(usize, Vec<FieldSpan>)>> = const { RefCell::new(None) };
}

/// Runs `f` and returns what it returned with every field that any [`ByteReader`] over `buffer`
/// (or a slice of it) read meanwhile on this thread, in reading order, offsets relative to the
/// start of `buffer`. Reads of other buffers are not recorded.
pub fn trace_fields<T>(buffer: &[u8], f: impl FnOnce() -> T) -> (T, Vec<FieldSpan>) {
    TRACE.with(|t| *t.borrow_mut() = Some((buffer.as_ptr() as usize, Vec::new())));
    let out = f();
    let (base, mut spans) = TRACE.with(|t| t.borrow_mut().take()).unwrap_or_default();
    let end = base + buffer.len();
    spans.retain(|s| s.offset >= base && s.offset + s.len <= end);
    for s in &mut spans {
        s.offset -= base;
    }
    (out, spans)
}

/// Appends values to a growing byte buffer.
#[derive(Debug, Default, Clone)]
pub struct ByteWriter {
    buf: Vec<u8>,
}

impl ByteWriter {
    /// An empty writer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes a model tag (e.g. the model identifier) and a format version; read it back with
    /// [`ByteReader::header`].
    pub fn header(&mut self, tag: &str, version: u32) {
        self.str(tag);
        self.u32(version);
    }

    /// Raw bytes without a length prefix (magic numbers).
    pub fn raw(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// One byte.
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }

    /// Four bytes, little-endian.
    pub fn u32(&mut self, v: u32) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// Eight bytes, little-endian.
    pub fn u64(&mut self, v: u64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// Four bytes, little-endian two's complement.
    pub fn i32(&mut self, v: i32) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// The eight IEEE-754 bytes of `v`, little-endian (bit-exact, NaN payloads included).
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }

    /// One byte, 0 or 1.
    pub fn bool(&mut self, v: bool) {
        self.buf.push(u8::from(v));
    }

    /// A `u64` byte length followed by the UTF-8 bytes.
    pub fn str(&mut self, v: &str) {
        self.bytes(v.as_bytes());
    }

    /// A `u64` length followed by the bytes.
    pub fn bytes(&mut self, v: &[u8]) {
        self.u64(v.len() as u64);
        self.buf.extend_from_slice(v);
    }

    /// A `u64` element count followed by each value as [`ByteWriter::f64`].
    pub fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        for x in v {
            self.f64(*x);
        }
    }

    /// Number of bytes written so far.
    pub fn len(&self) -> usize {
        self.buf.len()
    }

    /// True when nothing has been written.
    pub fn is_empty(&self) -> bool {
        self.buf.is_empty()
    }

    /// The bytes written so far.
    pub fn as_bytes(&self) -> &[u8] {
        &self.buf
    }

    /// Consumes the writer and returns its bytes.
    pub fn into_bytes(self) -> Vec<u8> {
        self.buf
    }
}

/// Reads values back from a byte slice, checking every bound.
#[derive(Debug, Clone)]
pub struct ByteReader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> ByteReader<'a> {
    /// A reader positioned at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, pos: 0 }
    }

    /// Current read offset [bytes from the start].
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], ModelError> {
        if n > self.remaining() {
            return Err(ModelError::BadState(format!(
                "truncated state: reading {what} needs {n} bytes at offset {}, only {} left",
                self.pos,
                self.remaining()
            )));
        }
        let out = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(out)
    }

    /// Records the field just read (`len` bytes ending at the current position) when tracing.
    fn record(&self, len: usize, kind: &'static str, what: &str) {
        TRACE.with(|t| {
            if let Some((_, spans)) = t.borrow_mut().as_mut() {
                spans.push(FieldSpan {
                    offset: self.bytes.as_ptr() as usize + self.pos - len,
                    len,
                    kind,
                    what: what.to_string(),
                });
            }
        });
    }

    fn array<const N: usize>(
        &mut self,
        kind: &'static str,
        what: &str,
    ) -> Result<[u8; N], ModelError> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N, what)?);
        self.record(N, kind, what);
        Ok(out)
    }

    /// Checks a tag and format version written by [`ByteWriter::header`]; returns the version.
    ///
    /// Fails when the tag differs (a state of another model) or the version is 0 or newer than
    /// `max_version`.
    pub fn header(&mut self, tag: &str, max_version: u32) -> Result<u32, ModelError> {
        let found = self.str("model tag")?;
        if found != tag {
            return Err(ModelError::BadState(format!(
                "state belongs to model `{}`, not `{tag}`",
                found.escape_debug()
            )));
        }
        let version = self.u32("format version")?;
        if version == 0 || version > max_version {
            return Err(ModelError::BadState(format!(
                "state format version {version} of `{tag}` is not supported (this build reads 1 to {max_version})"
            )));
        }
        Ok(version)
    }

    /// Checks that the next bytes equal `expected` (a magic number).
    pub fn expect_raw(&mut self, expected: &[u8], what: &str) -> Result<(), ModelError> {
        let found = self.take(expected.len(), what)?;
        self.record(expected.len(), "magic", what);
        if found != expected {
            return Err(ModelError::BadState(format!(
                "{what} mismatch at offset {}: expected {expected:02x?}, found {found:02x?}",
                self.pos - expected.len()
            )));
        }
        Ok(())
    }

    /// One byte.
    pub fn u8(&mut self, what: &str) -> Result<u8, ModelError> {
        Ok(self.array::<1>("u8", what)?[0])
    }

    /// Four bytes, little-endian.
    pub fn u32(&mut self, what: &str) -> Result<u32, ModelError> {
        Ok(u32::from_le_bytes(self.array("u32", what)?))
    }

    /// Eight bytes, little-endian.
    pub fn u64(&mut self, what: &str) -> Result<u64, ModelError> {
        Ok(u64::from_le_bytes(self.array("u64", what)?))
    }

    /// Four bytes, little-endian two's complement.
    pub fn i32(&mut self, what: &str) -> Result<i32, ModelError> {
        Ok(i32::from_le_bytes(self.array("i32", what)?))
    }

    /// An `f64` from its eight IEEE-754 bytes.
    pub fn f64(&mut self, what: &str) -> Result<f64, ModelError> {
        Ok(f64::from_bits(u64::from_le_bytes(self.array("f64", what)?)))
    }

    /// A finite `f64`; NaN and infinities are refused (for values that must be finite).
    pub fn finite_f64(&mut self, what: &str) -> Result<f64, ModelError> {
        let at = self.pos;
        let v = self.f64(what)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ModelError::BadState(format!(
                "corrupt state: {what} at offset {at} is {v}, expected a finite number"
            )))
        }
    }

    /// One byte that must be 0 or 1.
    pub fn bool(&mut self, what: &str) -> Result<bool, ModelError> {
        let at = self.pos;
        match self.array::<1>("bool", what)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(ModelError::BadState(format!(
                "corrupt state: {what} at offset {at} is {b}, expected 0 or 1"
            ))),
        }
    }

    /// A length prefix, checked against the bytes left (each item `item_size` bytes).
    fn len_prefix(&mut self, item_size: usize, what: &str) -> Result<usize, ModelError> {
        let at = self.pos;
        let n = u64::from_le_bytes(self.array("len", what)?);
        let fits = usize::try_from(n)
            .ok()
            .and_then(|n| n.checked_mul(item_size))
            .is_some_and(|bytes| bytes <= self.remaining());
        if !fits {
            return Err(ModelError::BadState(format!(
                "corrupt or truncated state: {what} at offset {at} claims {n} items of {item_size} bytes, only {} bytes left",
                self.remaining()
            )));
        }
        Ok(n as usize)
    }

    /// A length-prefixed byte blob.
    pub fn bytes(&mut self, what: &str) -> Result<&'a [u8], ModelError> {
        let n = self.len_prefix(1, what)?;
        self.take(n, what)
    }

    /// A length-prefixed UTF-8 string.
    pub fn str(&mut self, what: &str) -> Result<&'a str, ModelError> {
        let at = self.pos;
        let b = self.bytes(what)?;
        self.record(b.len(), "str", what);
        std::str::from_utf8(b).map_err(|e| {
            ModelError::BadState(format!(
                "corrupt state: {what} at offset {at} is not UTF-8 ({e})"
            ))
        })
    }

    /// A length-prefixed `f64` slice.
    pub fn f64s(&mut self, what: &str) -> Result<Vec<f64>, ModelError> {
        let n = self.len_prefix(8, what)?;
        (0..n).map(|_| self.f64(what)).collect()
    }

    /// A length-prefixed `f64` slice that must have exactly `len` items.
    pub fn f64s_exact(&mut self, len: usize, what: &str) -> Result<Vec<f64>, ModelError> {
        let at = self.pos;
        let v = self.f64s(what)?;
        if v.len() != len {
            return Err(ModelError::BadState(format!(
                "corrupt state: {what} at offset {at} has {} values, expected {len}",
                v.len()
            )));
        }
        Ok(v)
    }

    /// Succeeds only when every byte has been read (trailing bytes mean a foreign or corrupt state).
    pub fn finish(self) -> Result<(), ModelError> {
        if self.remaining() == 0 {
            Ok(())
        } else {
            Err(ModelError::BadState(format!(
                "corrupt state: {} unexpected trailing bytes at offset {}",
                self.remaining(),
                self.pos
            )))
        }
    }
}

/// 64-bit FNV-1a hash of `bytes`: a cheap checksum that detects flipped or shuffled bytes.
pub fn checksum64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.header("Demo", 2);
        w.u8(7);
        w.u32(0xdead_beef);
        w.u64(u64::MAX - 3);
        w.i32(-42);
        w.f64(-0.0);
        w.f64(f64::from_bits(0x7ff8_0000_0000_1234));
        w.bool(true);
        w.str("héllo");
        w.f64s(&[1.5, -2.25, 1e300]);
        w.bytes(&[1, 2, 3]);
        w.into_bytes()
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let bytes = sample();
        let mut r = ByteReader::new(&bytes);
        assert_eq!(r.header("Demo", 2).unwrap(), 2);
        assert_eq!(r.u8("a").unwrap(), 7);
        assert_eq!(r.u32("b").unwrap(), 0xdead_beef);
        assert_eq!(r.u64("c").unwrap(), u64::MAX - 3);
        assert_eq!(r.i32("d").unwrap(), -42);
        assert_eq!(r.f64("e").unwrap().to_bits(), (-0.0f64).to_bits());
        assert_eq!(r.f64("f").unwrap().to_bits(), 0x7ff8_0000_0000_1234);
        assert!(r.bool("g").unwrap());
        assert_eq!(r.str("h").unwrap(), "héllo");
        assert_eq!(r.f64s_exact(3, "i").unwrap(), vec![1.5, -2.25, 1e300]);
        assert_eq!(r.bytes("j").unwrap(), &[1, 2, 3]);
        r.finish().unwrap();
    }

    #[test]
    fn traced_fields_cover_every_byte_in_order() {
        let bytes = sample();
        let other = sample();
        let (res, spans) = trace_fields(&bytes, || {
            let mut r = ByteReader::new(&bytes);
            r.header("Demo", 2)?;
            ByteReader::new(&other).header("Demo", 2)?; // another buffer: not recorded
            r.u8("a")?;
            r.u32("b")?;
            r.u64("c")?;
            r.i32("d")?;
            r.f64("e")?;
            r.f64("f")?;
            r.bool("g")?;
            r.str("h")?;
            r.f64s("i")?;
            let blob = r.bytes("j")?;
            ByteReader::new(blob).u8("j0")?; // a nested reader over a slice of the buffer
            r.finish()
        });
        res.unwrap();
        let kinds: Vec<_> = spans.iter().map(|s| (s.kind, s.what.as_str())).collect();
        assert_eq!(
            kinds,
            [
                ("len", "model tag"),
                ("str", "model tag"),
                ("u32", "format version"),
                ("u8", "a"),
                ("u32", "b"),
                ("u64", "c"),
                ("i32", "d"),
                ("f64", "e"),
                ("f64", "f"),
                ("bool", "g"),
                ("len", "h"),
                ("str", "h"),
                ("len", "i"),
                ("f64", "i"),
                ("f64", "i"),
                ("f64", "i"),
                ("len", "j"),
                ("u8", "j0"),
            ]
        );
        let mut at = 0;
        for s in &spans {
            assert_eq!(s.offset, at, "{s:?}");
            at += s.len;
        }
        assert_eq!(at + 2, bytes.len()); // the two blob bytes the nested reader did not read
        // not tracing: nothing is recorded
        ByteReader::new(&bytes).header("Demo", 2).unwrap();
        assert!(TRACE.with(|t| t.borrow().is_none()));
    }

    #[test]
    fn every_truncation_is_refused_without_panicking() {
        let bytes = sample();
        for cut in 0..bytes.len() {
            let mut r = ByteReader::new(&bytes[..cut]);
            let res = (|| -> Result<(), ModelError> {
                r.header("Demo", 2)?;
                r.u8("a")?;
                r.u32("b")?;
                r.u64("c")?;
                r.i32("d")?;
                r.f64("e")?;
                r.f64("f")?;
                r.bool("g")?;
                r.str("h")?;
                r.f64s("i")?;
                r.bytes("j")?;
                Ok(())
            })();
            let err = res.expect_err("a truncated buffer must fail");
            assert!(err.to_string().contains("truncated"), "cut {cut}: {err}");
        }
    }

    #[test]
    fn foreign_tag_newer_version_and_bad_values_are_named() {
        let mut w = ByteWriter::new();
        w.header("Other", 1);
        let e = ByteReader::new(w.as_bytes()).header("Demo", 1).unwrap_err();
        assert!(e.to_string().contains("`Other`"), "{e}");

        let mut w = ByteWriter::new();
        w.header("Demo", 9);
        let e = ByteReader::new(w.as_bytes()).header("Demo", 1).unwrap_err();
        assert!(e.to_string().contains("version 9"), "{e}");

        let e = ByteReader::new(&[2]).bool("flag").unwrap_err();
        assert!(e.to_string().contains("flag"), "{e}");

        let mut w = ByteWriter::new();
        w.u64(u64::MAX);
        let e = ByteReader::new(w.as_bytes()).f64s("values").unwrap_err();
        assert!(e.to_string().contains("claims"), "{e}");

        let mut w = ByteWriter::new();
        w.f64(f64::INFINITY);
        assert!(ByteReader::new(w.as_bytes()).finite_f64("x").is_err());

        let e = ByteReader::new(&[0]).finish().unwrap_err();
        assert!(e.to_string().contains("trailing"), "{e}");
    }

    #[test]
    fn checksum_detects_a_flipped_bit() {
        let bytes = sample();
        let c = checksum64(&bytes);
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x10;
            assert_ne!(checksum64(&b), c);
        }
    }
}
