//! The XML structure of a VTU file: the file's settings (`<VTKFile>`), the piece's counts
//! (`<Piece>`), and each `<DataArray>` with the section it sits in, its attributes and its
//! text, not yet decoded. Appended raw data is not XML: the bytes after the `_` marker are cut
//! off before the XML is parsed.

use super::scalar::Scalar;
use super::{bad, clip};
use crate::io::IoError;
use crate::io::lex::try_push;
use quick_xml::events::{BytesStart, Event};
use std::borrow::Cow;

/// The file-wide settings of `<VTKFile>`.
#[derive(Clone, Copy)]
pub(super) struct FileInfo {
    pub big_endian: bool,
    pub header: Scalar,
    pub compressed: bool,
}

/// One `<DataArray>`, its data not yet decoded.
#[derive(Default)]
pub(super) struct Array<'a> {
    pub name: String,
    pub scalar: Option<Scalar>,
    pub components: usize,
    pub format: String,
    pub offset: Option<usize>,
    /// The element's text, borrowed from the file unless it came in several pieces.
    pub text: Cow<'a, [u8]>,
}

/// Where a `<DataArray>` sits.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Section {
    Other,
    Points,
    Cells,
    PointData,
}

/// What [`parse`] found: everything the mesh is built from, its data not yet decoded.
pub(super) struct Document<'a> {
    pub info: FileInfo,
    /// The piece's `NumberOfPoints`.
    pub points: usize,
    /// The piece's `NumberOfCells`.
    pub cells: usize,
    pub arrays: Vec<(Section, Array<'a>)>,
    /// The bytes after `<AppendedData>`'s `_` marker (empty without one).
    pub appended: &'a [u8],
    /// Whether `appended` is base64 (else raw).
    pub appended_base64: bool,
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

/// The structure of a VTU file (a leading UTF-8 byte-order mark skipped). Never panics,
/// whatever the bytes.
pub(super) fn parse(bytes: &[u8]) -> Result<Document<'_>, IoError> {
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
    Ok(Document { info, points: n, cells: m, arrays, appended, appended_base64 })
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
