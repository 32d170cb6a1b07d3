//! Long polylines built at test time from the corpus cube (`tr8_ha1_tc.stp`), as
//! `../shared/tools/bad_inputs.py` builds them (issue 13): a face bounded by an n-point
//! `POLYLINE` edge, and an n-point `POLYLINE` in a curve set. Meshing one used to take time
//! super-linear in n (over 120 s at 10⁵ points); here the work done (triangles, line
//! segments) must stay linear in n. Wall-clock figures against `cadre info` are in
//! BENCHMARKS.md ("Hostile inputs"); the full-size inputs run with `--ignored`. Skipped when
//! `../shared` is absent.

use std::path::Path;

use cadre_mesh::scene::Scene;
use cadre_mesh::{MeshParams, ModelMesh, mesh_model};
use cadre_step::syntax::StepFile;

const TAIL: &str = "ENDSEC;\nEND-ISO-10303-21;";

fn cube() -> Option<String> {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/step/tr8_ha1_tc.stp");
    match std::fs::read(&path) {
        Ok(b) => Some(String::from_utf8_lossy(&b).into_owned()),
        Err(_) => {
            eprintln!(
                "skipping: {} not found (clone without the shared data)",
                path.display()
            );
            None
        }
    }
}

/// The cube with its edge #74 replaced by an `n`-point straight POLYLINE along y.
fn polyedge(cube: &str, n: usize) -> String {
    let mut extra = String::new();
    for i in 0..n {
        let y = 100.0 * i as f64 / (n - 1) as f64;
        extra.push_str(&format!(
            "#{}=CARTESIAN_POINT('',(0.,{y},0.));\n",
            2_000_000 + i
        ));
    }
    let ids: Vec<String> = (0..n).map(|i| format!("#{}", 2_000_000 + i)).collect();
    extra.push_str(&format!("#3000000=POLYLINE('',({}));\n", ids.join(",")));
    let edge = "#74=EDGE_CURVE('#74',#11,#13,#29,.T.);";
    assert!(cube.contains(edge), "the cube has edge #74");
    cube.replace(edge, "#74=EDGE_CURVE('#74',#11,#13,#3000000,.T.);")
        .replace(TAIL, &format!("{extra}{TAIL}"))
}

/// The cube with an `n`-point POLYLINE (two points alternating) in a curve set.
fn polyset(cube: &str, n: usize) -> String {
    let rep = "#208=SHAPE_REPRESENTATION('#208',(#159,#201,#207),#203);";
    assert!(cube.contains(rep), "the cube has representation #208");
    let points = vec!["#10,#12"; n / 2].join(",");
    cube.replace(
        rep,
        "#208=SHAPE_REPRESENTATION('#208',(#159,#201,#207,#3000001),#203);",
    )
    .replace(
        TAIL,
        &format!(
            "#3000000=POLYLINE('',({points}));\n#3000001=GEOMETRIC_CURVE_SET('',(#3000000));\n{TAIL}"
        ),
    )
}

/// Meshes `text` as `cadre mesh` does and assembles its scene.
fn mesh(text: String) -> (cadre_brep::Model, ModelMesh, Scene) {
    let file = StepFile::parse(text.into_bytes()).expect("parses");
    let model = cadre_step::map_file(&file);
    let params = MeshParams::relative(&model, 0.001, 0.5);
    let mesh = mesh_model(&model, &params, None);
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh);
    (model, mesh, scene)
}

fn triangles(mesh: &ModelMesh) -> usize {
    mesh.faces.iter().flatten().map(|f| f.triangles.len()).sum()
}

fn line_segments(scene: &Scene) -> usize {
    scene.meshes.iter().map(|m| m.lines.len()).sum()
}

/// The face bounded by the long edge meshes completely, with work linear in the edge's
/// points: four times the points make at most about four times the triangles.
fn polyedge_scales(small: usize) {
    let Some(cube) = cube() else { return };
    let (plain_model, plain, _) = mesh(cube.clone());
    let (model, a, _) = mesh(polyedge(&cube, small));
    assert!(a.failures.is_empty(), "{:?}", a.failures);
    assert_eq!(model.faces.len(), plain_model.faces.len());
    let (_, b, _) = mesh(polyedge(&cube, 4 * small));
    assert!(b.failures.is_empty(), "{:?}", b.failures);
    let (ta, tb) = (triangles(&a), triangles(&b));
    // Negative control: the long edge really is in the mesh (its samples, capped by the
    // edge discretisation's budget, make the faces beside it gain triangles), or this test
    // measures nothing.
    assert!(
        ta > 10 * triangles(&plain),
        "{ta} vs plain {}",
        triangles(&plain)
    );
    assert!(
        tb <= 5 * ta,
        "{small} → {ta} triangles, {} → {tb}",
        4 * small
    );
}

/// The curve set's polyline is drawn (segments are added) with at most one segment per
/// point pair (the back-and-forth segments of this one merge).
fn polyset_scales(n: usize) {
    let Some(cube) = cube() else { return };
    let (_, _, plain) = mesh(cube.clone());
    let (_, _, scene) = mesh(polyset(&cube, n));
    let added = line_segments(&scene) - line_segments(&plain);
    assert!((1..n).contains(&added), "{n} points gave {added} segments");
}

#[test]
fn a_face_bounded_by_a_long_polyline_meshes_in_linear_work() {
    polyedge_scales(2_500);
}

#[test]
fn a_long_polyline_in_a_curve_set_is_drawn_in_linear_work() {
    polyset_scales(100_000);
}

/// The full sizes: a 10⁵-point edge (4·10⁵ for the scaling step) and a 10⁶-point
/// curve set.
#[test]
#[ignore = "full-size hostile inputs: cargo test --release -- --ignored"]
fn full_size_long_polylines() {
    polyedge_scales(100_000);
    polyset_scales(1_000_000);
}
