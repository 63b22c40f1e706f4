//! Reading a mesh file takes memory for the mesh, not a multiple of the file: the peak of the
//! bytes allocated while `read_mesh` runs, counted by a global allocator, stays under 3x the
//! file's size in every format.

use quadopt::io::{self, Format, MeshData};
use quadopt::synthetic::Synthetic;
use std::sync::Mutex;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::peak_of;

/// One measurement at a time (the test harness runs tests on several threads).
static SERIAL: Mutex<()> = Mutex::new(());

#[test]
fn reading_takes_less_than_three_times_the_file_size() {
    let _serial = SERIAL.lock().unwrap();
    // About 60k quads with holes: a few MB per format.
    let mesh = Synthetic::with_quads(60_000).generate();
    let points: Vec<[f64; 3]> = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
    let n = points.len();
    let mut data = MeshData::new(points, mesh.quads_as_given());
    let dir = std::env::temp_dir().join(format!("quadopt-mem-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for format in Format::ALL {
        // VTK carries fixed flags too.
        data.fixed = (format == Format::Vtk).then(|| (0..n).map(|i| i % 3 == 0).collect());
        let path = dir.join(format!("big.{}", format.extension()));
        io::write_mesh(&path, &data).unwrap();
        let size = std::fs::metadata(&path).unwrap().len() as usize;
        assert!(size > 2_000_000, "{format:?}: {size} bytes");
        let (back, peak) = peak_of(|| io::read_mesh(&path).unwrap());
        assert_eq!(back.points.len(), n);
        assert_eq!(back.quads, data.quads, "{format:?}");
        let ratio = peak as f64 / size as f64;
        println!("{format:?}: file {size} bytes, peak {peak} bytes while reading ({ratio:.2}x)");
        assert!(ratio < 3.0, "{format:?}: peak {peak} bytes for a {size}-byte file ({ratio:.2}x)");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reading_bytes_and_text_stays_under_three_times_too() {
    let _serial = SERIAL.lock().unwrap();
    let mesh = Synthetic::with_quads(30_000).generate();
    let points: Vec<[f64; 3]> = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
    let data = MeshData::new(points, mesh.quads_as_given());
    for format in Format::ALL {
        let text = io::write_mesh_string(format, &data).unwrap();
        let (back, peak) = peak_of(|| io::read_mesh_bytes(text.as_bytes(), format).unwrap());
        assert_eq!(back.quads, data.quads);
        // The text is already in memory here: the reader itself adds the mesh and little else.
        let ratio = peak as f64 / text.len() as f64;
        println!("{format:?} from bytes: text {} bytes, peak {peak} bytes ({ratio:.2}x)", text.len());
        assert!(ratio < 2.0, "{format:?}: {ratio:.2}x");
    }
}
