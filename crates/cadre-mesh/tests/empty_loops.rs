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

/// A torus (R 37.5, r 12.5, axis z at the origin) face in a shell, with `bounds` as its
/// bounds: `#21`, one edge loop whose edge curve names the missing vertices #998 and #999,
/// or `#26`, one loop of an edge from and to one vertex on the torus whose curve is missing.
fn torus_face(bounds: &str) -> String {
    format!(
        "{MM_CONTEXT}
#1=CARTESIAN_POINT('',(0.,0.,0.));
#2=DIRECTION('',(0.,0.,1.));
#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5=TOROIDAL_SURFACE('',#4,37.5,12.5);
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
