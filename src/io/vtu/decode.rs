//! The data of a `<DataArray>`: ASCII text, or a binary block (a header of sizes, then the
//! data, zlib-compressed in blocks or not) given inline as base64 (`binary`) or in the
//! appended data (`appended`, raw or base64), in either byte order, with UInt32 or UInt64
//! headers. Every size a header declares is checked against what the piece's counts need and
//! against the bytes present before anything is allocated or decompressed.

use super::bad;
use super::clip;
use super::scalar::Scalar;
use super::xml::{Array, FileInfo};
use crate::io::lex::try_vec;
use crate::io::{Encoding, IoError};
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use std::io::Read;

/// A data array's content before conversion.
enum Raw<'t> {
    Ascii(&'t [u8]),
    Binary(Scalar, Vec<u8>),
}

pub(super) struct Decoder<'a> {
    info: FileInfo,
    appended: &'a [u8],
    appended_base64: bool,
    used_binary: bool,
    used_appended: bool,
}

impl<'a> Decoder<'a> {
    /// A decoder of the arrays of a file with settings `info` and appended data `appended`
    /// (base64 or raw).
    pub fn new(info: FileInfo, appended: &'a [u8], appended_base64: bool) -> Decoder<'a> {
        Decoder { info, appended, appended_base64, used_binary: false, used_appended: false }
    }

    /// The encoding of the arrays decoded so far: appended if any was, else binary if any
    /// was, else ASCII.
    pub fn encoding(&self) -> Encoding {
        match (self.used_appended, self.used_binary) {
            (true, _) => Encoding::Appended,
            (false, true) => Encoding::Binary,
            _ => Encoding::Ascii,
        }
    }

    /// The `count` values of `array` as doubles.
    pub fn reals(&mut self, array: &Array, count: usize) -> Result<Vec<f64>, IoError> {
        let (scalar, bytes) = match self.bytes(array, count)? {
            Raw::Ascii(text) => return ascii_values(text, count, &array.name, |t| t.parse::<f64>().ok()),
            Raw::Binary(scalar, bytes) => (scalar, bytes),
        };
        let mut out = try_vec(count, "values")?;
        out.extend(bytes.chunks_exact(scalar.size()).map(|c| scalar.decode(&self.little(c))));
        Ok(out)
    }

    /// The `count` values of `array` as exact integers (an integer type, or ASCII integers).
    pub fn ints(&mut self, array: &Array, count: usize) -> Result<Vec<i64>, IoError> {
        let name = &array.name;
        let (scalar, bytes) = match self.bytes(array, count)? {
            Raw::Ascii(text) => return ascii_values(text, count, name, |t| t.parse::<i64>().ok()),
            Raw::Binary(scalar, bytes) => (scalar, bytes),
        };
        let mut out = try_vec(count, "values")?;
        for c in bytes.chunks_exact(scalar.size()) {
            let v = scalar.decode_int(&self.little(c));
            out.push(v.ok_or_else(|| bad(format!("DataArray {name:?} must hold integers below 2^63")))?);
        }
        Ok(out)
    }

    /// One element's bytes in little-endian order, padded to 8.
    fn little(&self, chunk: &[u8]) -> [u8; 8] {
        let mut b = [0u8; 8];
        b[..chunk.len()].copy_from_slice(chunk);
        if self.info.big_endian {
            b[..chunk.len()].reverse();
        }
        b
    }

    /// The data of `array`: its ASCII text, or its `count` elements' bytes.
    fn bytes<'t>(&mut self, array: &'t Array, count: usize) -> Result<Raw<'t>, IoError> {
        let scalar = array.scalar.ok_or_else(|| bad(format!("DataArray {:?} has no type", array.name)))?;
        let name = &array.name;
        let bytes = match array.format.as_str() {
            "ascii" => return Ok(Raw::Ascii(&array.text)),
            "binary" => {
                self.used_binary = true;
                let text: Vec<u8> = array.text.iter().copied().filter(|b| !b.is_ascii_whitespace()).collect();
                self.block_base64(&text, scalar, count, name)?
            }
            "appended" => {
                self.used_appended = true;
                let offset =
                    array.offset.ok_or_else(|| bad(format!("appended DataArray {name:?} has no offset")))?;
                let data = self.appended.get(offset..).ok_or_else(|| {
                    bad(format!(
                        "DataArray {name:?}: offset {offset} is past the appended data (truncated file?)"
                    ))
                })?;
                if self.appended_base64 {
                    let text: Vec<u8> = data.iter().copied().filter(|b| !b.is_ascii_whitespace()).collect();
                    self.block_base64(&text, scalar, count, name)?
                } else {
                    self.block_raw(data, scalar, count, name)?
                }
            }
            f => return Err(bad(format!("DataArray {name:?}: format \"{}\"", clip(f)))),
        };
        Ok(Raw::Binary(scalar, bytes))
    }

    fn word(&self, b: &[u8]) -> u64 {
        let size = self.info.header.size();
        let mut x = [0u8; 8];
        x[..size].copy_from_slice(&b[..size]);
        if self.info.big_endian {
            x[..size].reverse();
        }
        u64::from_le_bytes(x)
    }

    /// A binary block from raw bytes: header, then data (compressed: in blocks).
    fn block_raw(&self, data: &[u8], scalar: Scalar, count: usize, name: &str) -> Result<Vec<u8>, IoError> {
        let expected = count.checked_mul(scalar.size()).ok_or_else(|| bad("array too large"))?;
        let ws = self.info.header.size();
        let short = || bad(format!("DataArray {name:?}: the data ends early (truncated file?)"));
        if !self.info.compressed {
            let header = data.get(..ws).ok_or_else(short)?;
            check_size(self.word(header), expected, name)?;
            return Ok(data.get(ws..ws + expected).ok_or_else(short)?.to_vec());
        }
        let head = data.get(..3 * ws).ok_or_else(short)?;
        let (blocks, header_len) = self.compressed_header(head, expected, name)?;
        let header = data.get(..header_len).ok_or_else(short)?;
        let sizes: Vec<usize> = (0..blocks).map(|i| self.word(&header[(3 + i) * ws..]) as usize).collect();
        let total: usize = sizes.iter().try_fold(0usize, |a, &s| a.checked_add(s)).ok_or_else(short)?;
        let body =
            data.get(header_len..header_len.checked_add(total).ok_or_else(short)?).ok_or_else(short)?;
        inflate_blocks(
            body,
            &sizes,
            self.word(&head[ws..]) as usize,
            self.word(&head[2 * ws..]) as usize,
            expected,
            name,
        )
    }

    /// Checks a compressed header's first three words: (block count, header length in bytes).
    fn compressed_header(&self, head: &[u8], expected: usize, name: &str) -> Result<(usize, usize), IoError> {
        let ws = self.info.header.size();
        // Base64 padding inside the first words decodes to fewer bytes than they need.
        if head.len() < 3 * ws {
            return Err(bad(format!("DataArray {name:?}: the compression header ends early")));
        }
        let (blocks, block, last) = (self.word(head), self.word(&head[ws..]), self.word(&head[2 * ws..]));
        let total = if blocks == 0 {
            0
        } else {
            (blocks - 1)
                .checked_mul(block)
                .and_then(|x| x.checked_add(if last == 0 { block } else { last }))
                .ok_or_else(|| bad(format!("DataArray {name:?}: bad compression header")))?
        };
        check_size(total, expected, name)?;
        if blocks > 0 && (block == 0 || last > block) {
            return Err(bad(format!("DataArray {name:?}: bad compression header")));
        }
        let header_len = (3 + blocks as usize) * ws;
        Ok((blocks as usize, header_len))
    }

    /// A binary block from base64 text: VTK encodes the header and the data separately (each
    /// padded); some writers encode them as one stream. Both are read.
    fn block_base64(
        &self,
        text: &[u8],
        scalar: Scalar,
        count: usize,
        name: &str,
    ) -> Result<Vec<u8>, IoError> {
        let ws = self.info.header.size();
        let expected = count.checked_mul(scalar.size()).ok_or_else(|| bad("array too large"))?;
        let decode =
            |t: &[u8]| BASE64.decode(t).map_err(|e| bad(format!("DataArray {name:?}: bad base64 ({e})")));
        let chars = |bytes: usize| bytes.div_ceil(3) * 4;
        let short = || bad(format!("DataArray {name:?}: the data ends early (truncated file?)"));
        let header_len = if self.info.compressed {
            // The first 3 words take 4 x ws characters whichever way the stream was cut.
            let head = decode(text.get(..4 * ws).ok_or_else(short)?)?;
            self.compressed_header(&head, expected, name)?.1
        } else {
            ws
        };
        let hc = chars(header_len);
        let head_text = text.get(..hc).ok_or_else(short)?;
        let raw = if head_text.last() == Some(&b'=') || header_len % 3 == 0 {
            // Separate streams (or aligned, where both readings agree).
            let mut raw = decode(head_text)?;
            raw.truncate(header_len);
            let rest = &text[hc..];
            // Only as many characters as the data can need: appended base64 goes on.
            let mut body = decode_prefix(rest, name)?;
            raw.append(&mut body);
            raw
        } else {
            decode_prefix(text, name)?
        };
        self.block_raw(&raw, scalar, count, name)
    }
}

/// Decodes the first padded base64 stream of `text` (up to its padding or the end).
fn decode_prefix(text: &[u8], name: &str) -> Result<Vec<u8>, IoError> {
    let end = match text.iter().position(|&b| b == b'=') {
        Some(p) => {
            let mut e = p;
            while e < text.len() && text[e] == b'=' {
                e += 1;
            }
            e
        }
        None => text.len() - text.len() % 4,
    };
    BASE64.decode(&text[..end]).map_err(|e| bad(format!("DataArray {name:?}: bad base64 ({e})")))
}

fn check_size(declared: u64, expected: usize, name: &str) -> Result<(), IoError> {
    if declared != expected as u64 {
        return Err(bad(format!(
            "DataArray {name:?} holds {declared} bytes where the piece's counts need {expected}"
        )));
    }
    Ok(())
}

/// Inflates zlib blocks of compressed `sizes` into `expected` bytes: every block but the
/// last is `block` bytes, the last `last` (0: a full block).
fn inflate_blocks(
    body: &[u8],
    sizes: &[usize],
    block: usize,
    last: usize,
    expected: usize,
    name: &str,
) -> Result<Vec<u8>, IoError> {
    let mut out = try_vec(expected, "decompressed data")?;
    let mut at = 0;
    for (i, &size) in sizes.iter().enumerate() {
        let want = if i + 1 == sizes.len() && last != 0 { last } else { block };
        let before = out.len();
        let mut z = flate2::read::ZlibDecoder::new(&body[at..at + size]);
        // At most one byte more than the block may hold, so a lying block is caught cheaply.
        (&mut z)
            .take(want as u64 + 1)
            .read_to_end(&mut out)
            .map_err(|e| bad(format!("DataArray {name:?}: zlib block {i}: {e}")))?;
        if out.len() - before != want {
            return Err(bad(format!(
                "DataArray {name:?}: zlib block {i} holds {} bytes, {want} declared",
                out.len() - before
            )));
        }
        at += size;
    }
    Ok(out)
}

/// ASCII values: exactly `count` of them, each parsed by `parse`.
fn ascii_values<T>(
    text: &[u8],
    count: usize,
    name: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>, IoError> {
    let text = String::from_utf8_lossy(text);
    let mut out = try_vec(count, "values")?;
    for (i, t) in text.split_ascii_whitespace().enumerate() {
        if i == count {
            let total = text.split_ascii_whitespace().count();
            return Err(bad(format!(
                "DataArray {name:?} holds {total} values where the piece's counts need {count}"
            )));
        }
        out.push(
            parse(t).ok_or_else(|| bad(format!("DataArray {name:?}: {:?} is not a valid value", clip(t))))?,
        );
    }
    if out.len() != count {
        return Err(bad(format!(
            "DataArray {name:?} holds {} values where the piece's counts need {count}",
            out.len()
        )));
    }
    Ok(out)
}
