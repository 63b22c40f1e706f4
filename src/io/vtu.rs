//! VTK XML UnstructuredGrid (`.vtu`), ParaView's own format: quads (cell type 9), the point
//! data array `fixed` read as the fixed flags, and the arrays of [`MeshData`] written.
//!
//! Read: data arrays in `ascii`, inline `binary` (base64) and `appended` (raw or base64)
//! form, little- or big-endian, UInt32 or UInt64 block headers, uncompressed or compressed
//! with `vtkZLibDataCompressor` (ParaView's default); any other compressor is an error that
//! names it. Written: Float64 points, Int64 connectivity and offsets, UInt8 types and flags,
//! little-endian with UInt64 headers, in [`MeshData::encoding`], zlib-compressed when
//! [`MeshData::compressed`].
//!
//! The XML is parsed with `quick-xml`, zlib by `flate2`, base64 by `base64`. `vtkio` (the
//! crate that reads and writes XML VTK) was not used: its XML support is in 0.7, which is a
//! release candidate only (0.7.0-rc2), and its reader does not document that it never panics,
//! which the fuzz targets require. Appended raw data is not XML: the bytes after the `_`
//! marker are cut off before the XML is parsed.
//!
//! Every size a header declares is checked against what the XML declares (points x 3, cells)
//! and against the bytes present before anything is allocated or decompressed.

use super::lex::{try_push, try_vec};
use super::{Encoding, IoError, MeshData, Num};
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use quick_xml::events::{BytesStart, Event};
use std::borrow::Cow;
use std::io::{Read, Write};

/// VTK's cell type of a quad.
const VTK_QUAD: i64 = 9;

/// The block size the writer compresses with (VTK's default).
const BLOCK: usize = 32 * 1024;

fn bad(message: impl Into<String>) -> IoError {
    IoError::Malformed(message.into())
}

/// A data array's element type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Result<Scalar, IoError> {
        Ok(match name {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" | "UnsignedChar" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return Err(IoError::Unsupported(format!("VTU data type {:?}", clip(name)))),
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    /// The value of one element of `bytes` (exactly `size()` of them, little-endian).
    fn decode(self, b: &[u8]) -> f64 {
        let a = |n: usize| {
            let mut x = [0u8; 8];
            x[..n].copy_from_slice(&b[..n]);
            x
        };
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::I64 => i64::from_le_bytes(a(8)) as f64,
            Scalar::U64 => u64::from_le_bytes(a(8)) as f64,
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(a(8)),
        }
    }

    /// Integers of 64 bits are kept exact (an index above 2^53 is out of range anyway).
    fn decode_int(self, b: &[u8]) -> Option<i64> {
        match self {
            Scalar::I64 => Some(i64::from_le_bytes(b[..8].try_into().ok()?)),
            Scalar::U64 => i64::try_from(u64::from_le_bytes(b[..8].try_into().ok()?)).ok(),
            Scalar::F32 | Scalar::F64 => None,
            _ => Some(self.decode(b) as i64),
        }
    }
}

/// The file-wide settings of `<VTKFile>`.
#[derive(Clone, Copy)]
struct FileInfo {
    big_endian: bool,
    header: Scalar,
    compressed: bool,
}

/// One `<DataArray>`, its data not yet decoded.
#[derive(Default)]
struct Array<'a> {
    name: String,
    scalar: Option<Scalar>,
    components: usize,
    format: String,
    offset: Option<usize>,
    /// The element's text, borrowed from the file unless it came in several pieces.
    text: Cow<'a, [u8]>,
}

/// Where a `<DataArray>` sits.
#[derive(Clone, Copy, PartialEq)]
enum Section {
    Other,
    Points,
    Cells,
    PointData,
}

/// A data array's content before conversion.
enum Raw<'t> {
    Ascii(&'t [u8]),
    Binary(Scalar, Vec<u8>),
}

fn clip(s: &str) -> String {
    super::lex::clip(s)
}

fn attr(e: &BytesStart<'_>, key: &str) -> Result<Option<String>, IoError> {
    for a in e.attributes() {
        let a = a.map_err(|err| bad(format!("bad XML attribute: {err}")))?;
        if a.key.as_ref() == key.as_bytes() {
            return Ok(Some(String::from_utf8_lossy(&a.value).trim().to_string()));
        }
    }
    Ok(None)
}

fn count_attr(e: &BytesStart<'_>, key: &str) -> Result<usize, IoError> {
    let v = attr(e, key)?.ok_or_else(|| bad(format!("<Piece> has no {key}")))?;
    v.parse().map_err(|_| bad(format!("{key}=\"{}\" is not a count", clip(&v))))
}

/// Reads a VTU file. Never panics, whatever the bytes.
pub(super) fn read(bytes: &[u8]) -> Result<MeshData, IoError> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    // The appended block (raw bytes, not XML) is cut off first.
    let (xml, appended, appended_base64) = split_appended(bytes)?;
    let mut reader = quick_xml::Reader::from_reader(xml);
    reader.config_mut().check_end_names = false;
    let mut info: Option<FileInfo> = None;
    let mut counts: Option<(usize, usize)> = None;
    let mut section = Section::Other;
    let mut arrays: Vec<(Section, Array)> = Vec::new();
    let mut current: Option<Array> = None;
    // Elements nested in the current data array (VTK writes `<InformationKey>` there): their
    // text is not data.
    let mut nested = 0usize;
    let mut pieces = 0;
    loop {
        let event = reader.read_event().map_err(|e| bad(format!("bad XML: {e}")))?;
        match event {
            Event::Start(_) if current.is_some() => nested += 1,
            Event::Start(e) => open(&e, &mut info, &mut counts, &mut section, &mut current, &mut pieces)?,
            Event::Empty(_) if current.is_some() => {}
            Event::Empty(e) => {
                // An appended array has no content: `<DataArray ... offset="..."/>`.
                open(&e, &mut info, &mut counts, &mut section, &mut current, &mut pieces)?;
                if let Some(a) = current.take() {
                    try_push(&mut arrays, (section, a), "data arrays")?;
                }
                if matches!(e.name().as_ref(), b"Points" | b"Cells" | b"PointData" | b"CellData") {
                    section = Section::Other;
                }
            }
            Event::End(_) if nested > 0 => nested -= 1,
            Event::Text(t) if nested == 0 => {
                if let Some(a) = current.as_mut() {
                    let t = t.into_inner();
                    if a.text.is_empty() {
                        a.text = t;
                    } else {
                        a.text.to_mut().extend_from_slice(&t);
                    }
                }
            }
            Event::End(e) => match e.name().as_ref() {
                b"DataArray" => {
                    if let Some(a) = current.take() {
                        try_push(&mut arrays, (section, a), "data arrays")?;
                    }
                }
                b"Points" | b"Cells" | b"PointData" | b"CellData" => section = Section::Other,
                _ => {}
            },
            Event::GeneralRef(_) if current.is_some() && nested == 0 => {
                return Err(bad("an entity reference inside a data array"));
            }
            Event::Eof => break,
            _ => {}
        }
    }
    let info = info.ok_or_else(|| bad("not a VTK XML file (no <VTKFile>)"))?;
    let (n, m) = counts.ok_or_else(|| bad("the file has no <Piece>"))?;
    let mut ctx = Decoder { info, appended, appended_base64, used_binary: false, used_appended: false };

    let find = |sec: Section, name: Option<&str>| {
        arrays.iter().position(|(s, a)| *s == sec && name.is_none_or(|nm| a.name == nm))
    };
    let points_at = find(Section::Points, None).ok_or_else(|| bad("<Points> has no <DataArray>"))?;
    let pa = &arrays[points_at].1;
    if pa.components != 3 {
        return Err(bad(format!("points have {} components (3 expected)", pa.components)));
    }
    let coords = ctx.reals(pa, n.checked_mul(3).ok_or_else(|| bad("too many points"))?)?;
    let mut points = try_vec(n, "points")?;
    points.extend(coords.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));

    let cell = |name: &str| {
        find(Section::Cells, Some(name)).ok_or_else(|| bad(format!("<Cells> has no DataArray {name:?}")))
    };
    let (ci, oi, ti) = (cell("connectivity")?, cell("offsets")?, cell("types")?);
    let ints = |ctx: &mut Decoder<'_>, i: usize, count: usize| ctx.ints(&arrays[i].1, count);
    let types = ints(&mut ctx, ti, m)?;
    let offsets = ints(&mut ctx, oi, m)?;
    let connectivity = ints(&mut ctx, ci, m.checked_mul(4).ok_or_else(|| bad("too many cells"))?)?;
    let mut quads = try_vec(m, "quads")?;
    let mut start = 0i64;
    for c in 0..m {
        if types[c] != VTK_QUAD {
            return Err(IoError::Unsupported(format!(
                "cell {c} is of VTK type {}; only quads (type 9) are read",
                types[c]
            )));
        }
        if offsets[c] != start + 4 {
            return Err(bad(format!(
                "offsets: cell {c} ends at {} after starting at {start} (a quad has 4 vertices)",
                offsets[c]
            )));
        }
        let s = start as usize;
        let mut q = [0u32; 4];
        for (k, slot) in q.iter_mut().enumerate() {
            let v = connectivity[s + k];
            let out_of_range = IoError::Mesh(crate::Error::IndexOutOfRange {
                quad: c,
                corner: k,
                index: v as u64,
                vertex_count: n,
            });
            *slot = u32::try_from(v).ok().filter(|&v| (v as usize) < n).ok_or(out_of_range)?;
        }
        quads.push(q);
        start += 4;
    }
    let fixed = match find(Section::PointData, Some("fixed")) {
        Some(i) if arrays[i].1.components == 1 => {
            Some(ctx.reals(&arrays[i].1, n)?.iter().map(|&x| x != 0.0).collect())
        }
        _ => None,
    };
    let encoding = match (ctx.used_appended, ctx.used_binary) {
        (true, _) => Encoding::Appended,
        (false, true) => Encoding::Binary,
        _ => Encoding::Ascii,
    };
    Ok(MeshData { points, quads, fixed, encoding, compressed: info.compressed, ..MeshData::default() })
}

/// A start tag: the file's settings, the piece's counts, the section, or a new array.
fn open(
    e: &BytesStart<'_>,
    info: &mut Option<FileInfo>,
    counts: &mut Option<(usize, usize)>,
    section: &mut Section,
    current: &mut Option<Array>,
    pieces: &mut usize,
) -> Result<(), IoError> {
    match e.name().as_ref() {
        b"VTKFile" => *info = Some(file_info(e)?),
        b"Piece" => {
            *pieces += 1;
            if *pieces > 1 {
                return Err(IoError::Unsupported("VTU files with more than one <Piece>".into()));
            }
            *counts = Some((count_attr(e, "NumberOfPoints")?, count_attr(e, "NumberOfCells")?));
        }
        b"Points" => *section = Section::Points,
        b"Cells" => *section = Section::Cells,
        b"PointData" => *section = Section::PointData,
        b"CellData" | b"FieldData" => *section = Section::Other,
        b"DataArray" => {
            let number = |key: &str| -> Result<Option<usize>, IoError> {
                match attr(e, key)? {
                    Some(v) => {
                        v.parse().map(Some).map_err(|_| bad(format!("{key}=\"{}\" is not a count", clip(&v))))
                    }
                    None => Ok(None),
                }
            };
            *current = Some(Array {
                name: attr(e, "Name")?.unwrap_or_default(),
                scalar: attr(e, "type")?.map(|t| Scalar::parse(&t)).transpose()?,
                components: number("NumberOfComponents")?.unwrap_or(1),
                format: attr(e, "format")?.unwrap_or_else(|| "ascii".into()),
                offset: number("offset")?,
                text: Cow::Borrowed(&[]),
            });
        }
        _ => {}
    }
    Ok(())
}

fn file_info(e: &BytesStart<'_>) -> Result<FileInfo, IoError> {
    match attr(e, "type")?.as_deref() {
        Some("UnstructuredGrid") => {}
        Some(t) => {
            return Err(IoError::Unsupported(format!(
                "VTK XML {} files (UnstructuredGrid is read)",
                clip(t)
            )));
        }
        None => return Err(bad("<VTKFile> has no type")),
    }
    let big_endian = match attr(e, "byte_order")?.as_deref() {
        None | Some("LittleEndian") => false,
        Some("BigEndian") => true,
        Some(o) => return Err(bad(format!("byte_order=\"{}\" (LittleEndian or BigEndian)", clip(o)))),
    };
    let header = match attr(e, "header_type")?.as_deref() {
        None | Some("UInt32") => Scalar::U32,
        Some("UInt64") => Scalar::U64,
        Some(h) => return Err(bad(format!("header_type=\"{}\" (UInt32 or UInt64)", clip(h)))),
    };
    let compressed = match attr(e, "compressor")?.as_deref() {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(c) => {
            return Err(IoError::Unsupported(format!(
                "compressor {} (vtkZLibDataCompressor is read)",
                clip(c)
            )));
        }
    };
    Ok(FileInfo { big_endian, header, compressed })
}

/// Splits the file at `<AppendedData ...>`: the XML before it, the appended bytes after the
/// `_` marker (up to `</AppendedData>`), and whether they are base64.
fn split_appended(bytes: &[u8]) -> Result<(&[u8], &[u8], bool), IoError> {
    let Some(at) = find_bytes(bytes, b"<AppendedData") else { return Ok((bytes, &[], false)) };
    let rest = &bytes[at..];
    let close = rest.iter().position(|&b| b == b'>').ok_or_else(|| bad("unclosed <AppendedData> tag"))?;
    let tag = String::from_utf8_lossy(&rest[..close]);
    let base64 = if tag.contains("encoding=\"raw\"") || tag.contains("encoding='raw'") {
        false
    } else if tag.contains("base64") {
        true
    } else {
        return Err(bad("<AppendedData> encoding must be raw or base64"));
    };
    let body = &rest[close + 1..];
    let underscore =
        body.iter().position(|&b| b == b'_').ok_or_else(|| bad("<AppendedData> has no '_' marker"))?;
    if !body[..underscore].iter().all(u8::is_ascii_whitespace) {
        return Err(bad("<AppendedData> must start with '_'"));
    }
    let data = &body[underscore + 1..];
    let end = rfind_bytes(data, b"</AppendedData>").unwrap_or(data.len());
    Ok((&bytes[..at], &data[..end], base64))
}

fn find_bytes(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind_bytes(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

struct Decoder<'a> {
    info: FileInfo,
    appended: &'a [u8],
    appended_base64: bool,
    used_binary: bool,
    used_appended: bool,
}

impl Decoder<'_> {
    /// The `count` values of `array` as doubles.
    fn reals(&mut self, array: &Array, count: usize) -> Result<Vec<f64>, IoError> {
        let (scalar, bytes) = match self.bytes(array, count)? {
            Raw::Ascii(text) => return ascii_values(text, count, &array.name, |t| t.parse::<f64>().ok()),
            Raw::Binary(scalar, bytes) => (scalar, bytes),
        };
        let mut out = try_vec(count, "values")?;
        out.extend(bytes.chunks_exact(scalar.size()).map(|c| scalar.decode(&self.little(c))));
        Ok(out)
    }

    /// The `count` values of `array` as exact integers (an integer type, or ASCII integers).
    fn ints(&mut self, array: &Array, count: usize) -> Result<Vec<i64>, IoError> {
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

/// The values of one array to write.
enum Values {
    F64(Vec<f64>),
    I64(Vec<i64>),
    U8(Vec<u8>),
}

/// One array to write: its XML attributes and its values.
struct Out {
    name: &'static str,
    components: usize,
    values: Values,
}

impl Out {
    fn vtk_type(&self) -> &'static str {
        match self.values {
            Values::F64(_) => "Float64",
            Values::I64(_) => "Int64",
            Values::U8(_) => "UInt8",
        }
    }

    /// Little-endian bytes.
    fn bytes(&self) -> Vec<u8> {
        match &self.values {
            Values::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::U8(v) => v.clone(),
        }
    }

    /// ASCII values, separated by spaces (reals at round-trip precision).
    fn write_text(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let mut sep = "";
        match &self.values {
            Values::F64(v) => v.iter().try_for_each(|x| {
                write!(w, "{sep}{}", Num(*x))?;
                sep = " ";
                Ok(())
            }),
            Values::I64(v) => v.iter().try_for_each(|x| {
                write!(w, "{sep}{x}")?;
                sep = " ";
                Ok(())
            }),
            Values::U8(v) => v.iter().try_for_each(|x| {
                write!(w, "{sep}{x}")?;
                sep = " ";
                Ok(())
            }),
        }
    }
}

/// The block of one array: a UInt64 header and the data, zlib-compressed in blocks.
fn block(bytes: &[u8], compressed: bool) -> std::io::Result<(Vec<u8>, Vec<u8>)> {
    if !compressed {
        return Ok(((bytes.len() as u64).to_le_bytes().to_vec(), bytes.to_vec()));
    }
    let chunks: Vec<&[u8]> = bytes.chunks(BLOCK).collect();
    let last = chunks.last().map_or(0, |c| c.len());
    let mut header = Vec::new();
    for w in [chunks.len(), BLOCK, last] {
        header.extend_from_slice(&(w as u64).to_le_bytes());
    }
    let mut data = Vec::new();
    for c in chunks {
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(c)?;
        let c = z.finish()?;
        header.extend_from_slice(&(c.len() as u64).to_le_bytes());
        data.extend_from_slice(&c);
    }
    Ok((header, data))
}

pub(super) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
    let (n, m) = (data.points.len(), data.quads.len());
    let compressed = data.compressed && data.encoding != Encoding::Ascii;
    let flag = |f: &bool| u8::from(*f);
    let mut point_data = Vec::new();
    if let Some(f) = &data.fixed {
        point_data.push(Out {
            name: "fixed",
            components: 1,
            values: Values::U8(f.iter().map(flag).collect()),
        });
    }
    if let Some(f) = &data.corner {
        point_data.push(Out {
            name: "corner",
            components: 1,
            values: Values::U8(f.iter().map(flag).collect()),
        });
    }
    let cell_data: Vec<Out> = data
        .quality
        .iter()
        .map(|q| Out { name: "scaled_jacobian", components: 1, values: Values::F64(q.clone()) })
        .collect();
    let points = vec![Out {
        name: "Points",
        components: 3,
        values: Values::F64(data.points.iter().flatten().copied().collect()),
    }];
    let cells = vec![
        Out {
            name: "connectivity",
            components: 1,
            values: Values::I64(data.quads.iter().flatten().map(|&v| i64::from(v)).collect()),
        },
        Out { name: "offsets", components: 1, values: Values::I64((1..=m).map(|c| 4 * c as i64).collect()) },
        Out { name: "types", components: 1, values: Values::U8(vec![VTK_QUAD as u8; m]) },
    ];
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    let compressor = if compressed { " compressor=\"vtkZLibDataCompressor\"" } else { "" };
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>"
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(w, "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{m}\">")?;
    let mut appended: Vec<u8> = Vec::new();
    let sections =
        [("PointData", &point_data), ("CellData", &cell_data), ("Points", &points), ("Cells", &cells)];
    for (section, arrays) in sections {
        if arrays.is_empty() {
            continue;
        }
        writeln!(w, "      <{section}>")?;
        for a in arrays.iter() {
            let head = format!(
                "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"",
                a.vtk_type(),
                a.name,
                a.components
            );
            match data.encoding {
                Encoding::Ascii => {
                    writeln!(w, "{head} format=\"ascii\">")?;
                    write!(w, "          ")?;
                    a.write_text(w)?;
                    writeln!(w)?;
                    writeln!(w, "        </DataArray>")?;
                }
                Encoding::Binary => {
                    let (header, body) = block(&a.bytes(), compressed)?;
                    writeln!(w, "{head} format=\"binary\">")?;
                    writeln!(w, "          {}{}", BASE64.encode(&header), BASE64.encode(&body))?;
                    writeln!(w, "        </DataArray>")?;
                }
                Encoding::Appended => {
                    writeln!(w, "{head} format=\"appended\" offset=\"{}\"/>", appended.len())?;
                    let (header, body) = block(&a.bytes(), compressed)?;
                    appended.extend_from_slice(&header);
                    appended.extend_from_slice(&body);
                }
            }
        }
        writeln!(w, "      </{section}>")?;
    }
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    if data.encoding == Encoding::Appended {
        write!(w, "  <AppendedData encoding=\"raw\">\n   _")?;
        w.write_all(&appended)?;
        writeln!(w, "\n  </AppendedData>")?;
    }
    writeln!(w, "</VTKFile>")
}
