//! Reads every Mesquite quad test mesh in `../shared/meshes/mesquite` next to the repository
//! (when present; the directory is not part of the repository, so the tests skip with a
//! one-line message without it).

mod common;

use common::shared;
use quadopt::Error;
use quadopt::io::{self, Format, IoError, PlanarFrame, PlanarMesh};
use std::path::{Path, PathBuf};

fn mesquite(test: &str) -> Option<PathBuf> {
    shared::mesquite(&format!("{test} (the Mesquite meshes)"))
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for sub in ["tangled", "untangled"] {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            v.push(e.unwrap().path());
        }
    }
    v.sort();
    v
}

/// Expected outcome per file: Ok((points, quads, fixed count)) or the start of the error.
fn expected(name: &str) -> Result<(usize, usize, Option<usize>), &'static str> {
    Ok(match name {
        "bias-sphere-quads.vtk" | "paraboloid.vtk" | "quads_on_sphere_529.vtk" => return Err("not planar"),
        // A tilted plane stored with 7 significant digits: 1.0e-7 of its diagonal off its
        // best-fit plane, far more than rounding, so a surface by the one planarity rule.
        "quad_2_not_xy.vtk" => return Err("not planar"),
        // 24 triangles around its centre, then 216 quads.
        "polarMesh.vtk" => (241, 240, Some(24)),
        // Its cell counts say 3 but four indices follow: a broken file.
        "shashkov_quad_opt.vtk" => return Err("line 8328: expected a point index"),
        "hole_in_square.vtk" => (168, 140, Some(56)),
        "inverted-hole-1.vtk" => (96, 64, Some(64)),
        "par_untangle_original_quad_mesh.1.0.vtk" => (169, 144, Some(48)),
        "par_untangle_original_quad_mesh.2.0.vtk" | "par_untangle_original_quad_mesh.2.1.vtk" => {
            (104, 84, Some(27))
        }
        "rotsq.vtk" => (16, 9, Some(12)),
        "tangled_quad.vtk" => (36, 25, Some(20)),
        "copy-morph-for-ricoh.cub.vtk" => (15364, 13678, Some(3372)),
        "four_more_quads.vtk" | "square_quad_2.vtk" => (9, 4, Some(8)),
        "halfCirc.vtk" => (681, 640, Some(80)),
        "hole_scheme.vtk" => (84, 72, Some(24)),
        "hole_scheme_opp_bias.vtk" => (203, 174, Some(58)),
        "horse20x10_2_4.vtk" => (231, 200, Some(60)),
        "quads_4by2.vtk" | "quads_4by2_bad.vtk" => (15, 8, Some(12)),
        "shashkov_quad.vtk" => (4225, 4096, Some(256)),
        "shest_grid32.vtk" => (1089, 1024, Some(128)),
        "square_quad_10_rand.vtk" => (121, 100, Some(40)),
        "subdiv4x4_3_2_3x3.vtk" => (45, 36, Some(16)),
        "tfi_chevron24x24.vtk" | "ybiasqr24x24.vtk" => (625, 576, Some(96)),
        "tfi_horse10x4-12.vtk" | "tfi_horse10x4-14.vtk" => (55, 40, Some(28)),
        // Its CELLS line announces 80 values for 150; the per-cell counts are right.
        "unstrquad.vtk" => (41, 30, Some(20)),
        _ => panic!("unexpected file {name}"),
    })
}

#[test]
fn every_mesquite_mesh_reads_or_fails_precisely() {
    let Some(dir) = mesquite("every_mesquite_mesh_reads_or_fails_precisely") else { return };
    let all = files(&dir);
    assert!(all.len() >= 30, "{} files", all.len());
    for path in all {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let result = io::read_mesh(&path).and_then(|d| PlanarMesh::new(&d).map(|p| (d, p)));
        match (expected(&name), result) {
            (Ok((np, nq, nf)), Ok((data, planar))) => {
                let fixed = data.fixed.as_ref().map(|f| f.iter().filter(|&&x| x).count());
                assert_eq!((data.points.len(), data.quads.len(), fixed), (np, nq, nf), "{name}");
                // Every planar one lies in a plane x, y or z = const.
                assert!(matches!(planar.frame, PlanarFrame::Axis { .. }), "{name}");
                // Writing and reading back keeps everything, bit for bit.
                let text = io::write_mesh_string(Format::Vtk, &data).unwrap();
                assert_eq!(io::read_mesh_str(&text, Format::Vtk).unwrap(), data, "{name}");
            }
            (Err("not planar"), Err(IoError::Mesh(Error::NotPlanar { .. }))) => {}
            (Err(start), Err(e)) => {
                let msg = e.to_string();
                let msg = msg.strip_prefix(&format!("{}: ", path.display())).unwrap_or(&msg);
                assert!(msg.starts_with(start), "{name}: {msg}");
            }
            (want, got) => panic!("{name}: expected {want:?}, got {:?}", got.map(|_| ())),
        }
    }
}

#[test]
fn z_minus_5_and_clockwise_meshes_map_exactly() {
    let Some(dir) = mesquite("z_minus_5_and_clockwise_meshes_map_exactly") else { return };
    let data = io::read_mesh(dir.join("tangled/hole_in_square.vtk")).unwrap();
    let planar = PlanarMesh::new(&data).unwrap();
    assert_eq!(planar.frame, PlanarFrame::Axis { axis: 2, value: -5.0 });
    assert!(planar.mesh.has_clockwise_component());
    // Unchanged positions write back unchanged, quads as given.
    let mut copy = data.clone();
    planar.write_back(&mut copy);
    assert_eq!(copy, data);
}

/// The guarantees of the default options on real meshes from another smoother's suite: no
/// more inverted quads, a minimum never below the input's, fixed vertices bit-identical, and
/// every tangled input untangled (each of them has a valid configuration with its fixed
/// vertices: Mesquite's own untangled results). The 13678-quad copy-morph mesh is left out to
/// keep the suite fast.
#[test]
fn default_optimization_keeps_its_guarantees_on_the_mesquite_meshes() {
    let Some(dir) = mesquite("default_optimization_keeps_its_guarantees_on_the_mesquite_meshes") else {
        return;
    };
    let mut checked = 0;
    for path in files(&dir) {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if expected(&name).is_err() || name.starts_with("copy-morph") {
            continue;
        }
        let data = io::read_mesh(&path).unwrap();
        let mut planar = PlanarMesh::new(&data).unwrap();
        let before = planar.mesh.clone();
        let report = quadopt::optimize(&mut planar.mesh, &quadopt::Options::default()).unwrap();
        let (input, output) = (report.input, planar.mesh.quality());
        assert_eq!(output, report.output, "{name}");
        assert!(output.inverted <= input.inverted, "{name}: {input:?} -> {output:?}");
        assert!(output.min >= input.min, "{name}: {input:?} -> {output:?}");
        if path.parent().unwrap().ends_with("tangled") {
            assert_eq!(output.inverted, 0, "{name}: {:?}", report.tangled);
        }
        for (v, (a, b)) in before.points().iter().zip(planar.mesh.points()).enumerate() {
            if before.fixed()[v] {
                assert_eq!(
                    (a.x.to_bits(), a.y.to_bits()),
                    (b.x.to_bits(), b.y.to_bits()),
                    "{name}: vertex {v}"
                );
            }
        }
        checked += 1;
    }
    assert!(checked >= 25, "{checked} meshes checked");
}

/// Every test finds `../shared` through `common::shared`, relative to the repository: none
/// names a path of one machine (such as `/work/shared`) or looks for `../shared` on its own,
/// where a missing directory could go unsaid.
#[test]
fn tests_find_the_shared_data_only_relative_to_the_repository() {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    // Spelled in two pieces, so that this file does not match itself.
    let needles = [concat!("\"/", "work/"), concat!("../", "shared")];
    let mut offenders = Vec::new();
    for dir in [tests.clone(), tests.join("common")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "rs") || path.ends_with("common/shared.rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for (i, line) in text.lines().enumerate() {
                let code = line.trim_start();
                if !code.starts_with("//") && needles.iter().any(|n| code.contains(n)) {
                    offenders.push(format!("{}:{}: {code}", path.display(), i + 1));
                }
            }
        }
    }
    assert!(offenders.is_empty(), "use common::shared instead:\n{}", offenders.join("\n"));
}

/// Without `../shared`, the helper says on one line what is skipped and where it looked.
#[test]
fn a_missing_shared_directory_is_skipped_with_one_line_saying_why() {
    let base = std::env::temp_dir().join(format!("quadopt-no-shared-{}", std::process::id()));
    let root = base.join("repository");
    let looked = root.join("..").join("shared").join("meshes/mesquite");
    std::fs::create_dir_all(&root).unwrap();
    let line = shared::locate(&root, "meshes/mesquite", "the check").unwrap_err();
    assert!(line.starts_with("skipped: the check, because "), "{line}");
    assert!(line.contains(&format!("{} is not a directory", looked.display())), "{line}");
    assert!(!line.contains('\n'), "{line}");
    std::fs::create_dir_all(base.join("shared/meshes/mesquite")).unwrap();
    assert_eq!(shared::locate(&root, "meshes/mesquite", "the check"), Ok(looked));
    std::fs::remove_dir_all(&base).unwrap();
}
