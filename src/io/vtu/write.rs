//! Writing a VTU file: Float64 points, Int64 connectivity and offsets, UInt8 types and flags,
//! little-endian with UInt64 headers, in [`MeshData::encoding`], zlib-compressed in blocks of
//! 32 KiB when [`MeshData::compressed`].

use super::{VTK_QUAD, VTK_TRIANGLE};
use crate::face::{is_triangle, vertices};
use crate::io::{Encoding, MeshData, push_f64, push_int, write_items};
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use std::io::Write;

/// The block size the writer compresses with (VTK's default).
const BLOCK: usize = 32 * 1024;

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
        let sep = |b: &mut Vec<u8>, i: usize| {
            if i > 0 {
                b.push(b' ');
            }
        };
        match &self.values {
            Values::F64(v) => write_items(w, v, |b, i, &x| {
                sep(b, i);
                push_f64(b, x);
            }),
            Values::I64(v) => write_items(w, v, |b, i, &x| {
                sep(b, i);
                push_int(b, x);
            }),
            Values::U8(v) => write_items(w, v, |b, i, &x| {
                sep(b, i);
                push_int(b, x);
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

pub(in crate::io) fn write(w: &mut dyn Write, data: &MeshData) -> std::io::Result<()> {
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
    let offsets = data
        .quads
        .iter()
        .scan(0i64, |end, q| {
            *end += vertices(q).len() as i64;
            Some(*end)
        })
        .collect();
    let cells = vec![
        Out {
            name: "connectivity",
            components: 1,
            values: Values::I64(data.quads.iter().flat_map(vertices).map(|&v| i64::from(v)).collect()),
        },
        Out { name: "offsets", components: 1, values: Values::I64(offsets) },
        Out {
            name: "types",
            components: 1,
            values: Values::U8(
                data.quads
                    .iter()
                    .map(|q| if is_triangle(q) { VTK_TRIANGLE } else { VTK_QUAD } as u8)
                    .collect(),
            ),
        },
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
