//! A face whose loops all came out empty (every edge named a vertex that does not exist, as
//! a fuzzed file had it) is the whole of its closed surface for the trimmer; its box must be
//! that surface's too, or the model's box is empty, the relative deflection falls back to
//! 0.001 mm and a torus meshes into 384,792 triangles (1.1 s; a 60 s timeout under the
//! fuzzer).

#[path = "../../cadre-step/tests/common/mod.rs"]
mod common;

use cadre_geom::Accuracy;
use cadre_mesh::{MeshParams, mesh_model};
use common::{MM_CONTEXT, model};

/// A torus surface #5 (R 37.5, r 12.5, axis z at the origin), with the directions #2 (z) and
/// #3 (x).
const TORUS: &str = "
#1=CARTESIAN_POINT('',(0.,0.,0.));
#2=DIRECTION('',(0.,0.,1.));
#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5=TOROIDAL_SURFACE('',#4,37.5,12.5);";

/// A torus (R 37.5, r 12.5, axis z at the origin) face in a shell, with `bounds` as its
/// bounds: `#21`, one edge loop whose edge curve names the missing vertices #998 and #999,
/// or `#26`, one loop of an edge from and to one vertex on the torus whose curve is missing.
fn torus_face(bounds: &str) -> String {
    format!(
        "{MM_CONTEXT}{TORUS}
#10=CIRCLE('',#4,50.);
#11=EDGE_CURVE('',#998,#999,#10,.T.);
#12=ORIENTED_EDGE('',*,*,#11,.T.);
#20=EDGE_LOOP('',(#12));
#21=FACE_OUTER_BOUND('',#20,.T.);
#22=CARTESIAN_POINT('',(50.,0.,0.));
#23=VERTEX_POINT('',#22);
#25=EDGE_CURVE('',#23,#23,#9999,.T.);
#28=ORIENTED_EDGE('',*,*,#25,.T.);
#29=EDGE_LOOP('',(#28));
#26=FACE_OUTER_BOUND('',#29,.T.);
#30=ADVANCED_FACE('',({bounds}),#5,.T.);
#31=OPEN_SHELL('',(#30));
#32=SHELL_BASED_SURFACE_MODEL('',(#31));
#40=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#32),#900);"
    )
}

fn box_and_triangles(text: &str) -> (cadre_geom::BoundingBox, usize) {
    let m = model(text);
    let b = m.bbox(Accuracy::default());
    let params = MeshParams::relative(&m, 0.001, 0.5);
    let mesh = mesh_model(&m, &params, None);
    let triangles = mesh.faces.iter().flatten().map(|f| f.triangles.len()).sum();
    (b, triangles)
}

#[test]
fn a_face_with_only_empty_loops_is_bounded_as_its_whole_surface() {
    let (empty_loop, triangles) = box_and_triangles(&torus_face("#21"));
    assert!(!empty_loop.is_empty(), "the torus has a box");
    let (lo, hi) = (empty_loop.min, empty_loop.max);
    for (got, want) in [(lo.x, -50.0), (hi.x, 50.0), (lo.z, -12.5), (hi.z, 12.5)] {
        assert!((got - want).abs() < 1e-6, "{lo:?} – {hi:?}");
    }
    // Meshed at 0.001 of that box's diagonal, not at 0.001 mm.
    assert!((100..20_000).contains(&triangles), "{triangles} triangles");
    // Negative control: the same face written with no loop at all was already bounded so;
    // both readings agree.
    let (no_loop, _) = box_and_triangles(&torus_face(""));
    assert_eq!(no_loop, empty_loop);
}

#[test]
fn a_face_bounded_by_one_point_is_bounded_as_its_whole_surface() {
    // The loop is one point: the trimmer drops it and meshes the whole torus
    // (a fuzzed B-spline face of this kind had a one-point box: 96,348 triangles at the
    // 1e-7 mm deflection floor, 32 now).
    let (point_loop, triangles) = box_and_triangles(&torus_face("#26"));
    let (no_loop, whole) = box_and_triangles(&torus_face(""));
    assert_eq!(point_loop, no_loop);
    assert_eq!(triangles, whole);
}

/// A torus face whose one loop is a 0.01 mm circle on its outer equator, run so that the
/// face is the torus minus that hole: its edges span 0.02 mm, the face 100 mm.
fn torus_with_a_pinhole() -> String {
    format!(
        "{MM_CONTEXT}{TORUS}
#6=CARTESIAN_POINT('',(50.,0.,0.));
#7=DIRECTION('',(0.,1.,0.));
#8=AXIS2_PLACEMENT_3D('',#6,#3,#7);
#9=CIRCLE('',#8,0.01);
#10=CARTESIAN_POINT('',(50.,0.01,0.));
#11=VERTEX_POINT('',#10);
#12=EDGE_CURVE('',#11,#11,#9,.T.);
#13=ORIENTED_EDGE('',*,*,#12,.F.);
#20=EDGE_LOOP('',(#13));
#21=FACE_OUTER_BOUND('',#20,.T.);
#30=ADVANCED_FACE('',(#21),#5,.T.);
#31=OPEN_SHELL('',(#30));
#32=SHELL_BASED_SURFACE_MODEL('',(#31));
#40=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#32),#900);"
    )
}

#[test]
fn a_face_far_larger_than_its_edges_is_not_meshed_finer_than_its_own_size_allows() {
    let m = model(&torus_with_a_pinhole());
    // The relative deflection is taken of the edges' box: 2e-5 mm here.
    let params = MeshParams::relative(&m, 0.001, 0.5);
    assert!(params.deflection < 1e-4, "{}", params.deflection);
    let mesh = mesh_model(&m, &params, None);
    assert!(mesh.failures.is_empty(), "{:?}", mesh.failures);
    let triangles: usize = mesh.faces.iter().flatten().map(|f| f.triangles.len()).sum();
    assert!(mesh.truncated.is_empty(), "stopped at the point budget");
    // About what a torus needs at 10⁻⁵ of its 100 mm size, not the point budget.
    assert!(triangles < 400_000, "{triangles} triangles");
    assert!(
        mesh.repairs.iter().any(|r| r.note.contains("own size")),
        "{:?}",
        mesh.repairs
    );
    // Negative control: at 0.1 mm the face is meshed as asked, without the note.
    let coarse = MeshParams {
        deflection: 0.1,
        ..params
    };
    let mesh = mesh_model(&m, &coarse, None);
    assert!(mesh.repairs.iter().all(|r| !r.note.contains("own size")));
}
