//! Properties and measurements on small models written in STEP by hand: a box (line edges,
//! right angles, outward normals through a face written with `same_sense` false), a cylinder
//! (radius, circle length, parallel faces) and a face bounded by a B-spline edge.

use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;

use cadre_brep::measure::{
    CurveKind, SurfaceKind, angle_between_faces, edge_properties, face_properties, radius_of,
    vertex_distance,
};
use cadre_brep::{EdgeId, Entity, FaceId, Model, StepIndex};
use cadre_geom::Vec3;
use cadre_step::syntax::StepFile;

const CONTEXT: &str = "
#900=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904))
 GLOBAL_UNIT_ASSIGNED_CONTEXT((#901,#902,#903)) REPRESENTATION_CONTEXT('',''));
#901=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#902=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#903=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#901,'distance_accuracy_value','');
";

/// Reads `data` with the shared context; `rep` is the representation (#999) holding it.
fn model(data: &str, rep: &str) -> Model {
    let text = format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('t','',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{CONTEXT}{data}\n#999={rep};\n\
         ENDSEC;\nEND-ISO-10303-21;\n"
    );
    let file = StepFile::parse(text.into_bytes()).expect("parses");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    model
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// Appends numbered entities to STEP text.
struct Writer {
    next: u64,
    text: String,
}

impl Writer {
    fn add(&mut self, entity: String) -> u64 {
        let id = self.next;
        self.next += 1;
        let _ = writeln!(self.text, "#{id}={entity};");
        id
    }

    fn point(&mut self, p: Vec3) -> u64 {
        self.add(format!(
            "CARTESIAN_POINT('',({:.6},{:.6},{:.6}))",
            p.x, p.y, p.z
        ))
    }

    fn direction(&mut self, d: Vec3) -> u64 {
        self.add(format!("DIRECTION('',({:.6},{:.6},{:.6}))", d.x, d.y, d.z))
    }
}

/// An edge of a box by its two corner indices (`x + 2y + 4z`), lower first.
type Corners = (usize, usize);

/// The names of a box's faces by outward normal, in the order [`box_solid`] writes them.
const BOX_FACES: [&str; 6] = ["-z", "+z", "-y", "+y", "-x", "+x"];

/// A box `[0, size]` with its corner at `origin` as a `MANIFOLD_SOLID_BREP` #100. The +y
/// face's plane is written with its normal pointing inward and the face `same_sense` false.
/// Returns the text and the STEP ids of the faces (in [`BOX_FACES`] order) and of the edges
/// (by their two corner indices, `x + 2y + 4z`).
fn box_solid(origin: Vec3, size: Vec3) -> (String, Vec<u64>, Vec<(Corners, u64)>) {
    let mut w = Writer {
        next: 1000,
        text: String::new(),
    };
    let corner = |i: usize| {
        origin
            + Vec3::new(
                (i & 1) as f64 * size.x,
                ((i >> 1) & 1) as f64 * size.y,
                ((i >> 2) & 1) as f64 * size.z,
            )
    };
    let vertices: Vec<u64> = (0..8)
        .map(|i| {
            let p = w.point(corner(i));
            w.add(format!("VERTEX_POINT('',#{p})"))
        })
        .collect();
    // Loops counter-clockwise seen from outside, with the outward normal.
    let faces: [([usize; 4], Vec3); 6] = [
        ([0, 2, 3, 1], -Vec3::Z),
        ([4, 5, 7, 6], Vec3::Z),
        ([0, 1, 5, 4], -Vec3::Y),
        ([2, 6, 7, 3], Vec3::Y),
        ([0, 4, 6, 2], -Vec3::X),
        ([1, 3, 7, 5], Vec3::X),
    ];
    let mut edges: Vec<(Corners, u64)> = Vec::new();
    let mut face_ids = Vec::new();
    for (corners, normal) in faces {
        let mut oriented = Vec::new();
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let key = (a.min(b), a.max(b));
            let edge = match edges.iter().find(|(k, _)| *k == key) {
                Some(&(_, id)) => id,
                None => {
                    let (p, q) = (corner(key.0), corner(key.1));
                    let start = w.point(p);
                    let dir = w.direction((q - p).normalize());
                    let vec = w.add(format!("VECTOR('',#{dir},{:.6})", (q - p).length()));
                    let line = w.add(format!("LINE('',#{start},#{vec})"));
                    let (v0, v1) = (vertices[key.0], vertices[key.1]);
                    let id = w.add(format!("EDGE_CURVE('',#{v0},#{v1},#{line},.T.)"));
                    edges.push((key, id));
                    id
                }
            };
            let forward = if a < b { ".T." } else { ".F." };
            oriented.push(w.add(format!("ORIENTED_EDGE('',*,*,#{edge},{forward})")));
        }
        let list = oriented
            .iter()
            .map(|id| format!("#{id}"))
            .collect::<Vec<_>>()
            .join(",");
        let lp = w.add(format!("EDGE_LOOP('',({list}))"));
        let bound = w.add(format!("FACE_OUTER_BOUND('',#{lp},.T.)"));
        // The +y face: plane normal inward, face reversed against it.
        let inward = normal == Vec3::Y;
        let o = w.point(corner(corners[0]));
        let axis = w.direction(if inward { -normal } else { normal });
        let reference = w.direction(corner(corners[1]) - corner(corners[0]));
        let place = w.add(format!("AXIS2_PLACEMENT_3D('',#{o},#{axis},#{reference})"));
        let plane = w.add(format!("PLANE('',#{place})"));
        let sense = if inward { ".F." } else { ".T." };
        face_ids.push(w.add(format!("ADVANCED_FACE('',(#{bound}),#{plane},{sense})")));
    }
    let list = face_ids
        .iter()
        .map(|id| format!("#{id}"))
        .collect::<Vec<_>>()
        .join(",");
    let shell = w.add(format!("CLOSED_SHELL('',({list}))"));
    let _ = writeln!(w.text, "#100=MANIFOLD_SOLID_BREP('',#{shell});");
    (w.text, face_ids, edges)
}

fn box_model() -> (Model, StepIndex, Vec<FaceId>, Vec<(Corners, EdgeId)>) {
    let (text, faces, edges) = box_solid(Vec3::new(1.0, 2.0, 3.0), Vec3::new(10.0, 20.0, 30.0));
    let m = model(
        &text,
        "ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#100),#900)",
    );
    let idx = StepIndex::new(&m);
    let faces = faces.iter().map(|&s| idx.face(s).expect("face")).collect();
    let edges = edges
        .iter()
        .map(|&(k, s)| (k, idx.edge(s).expect("edge")))
        .collect();
    (m, idx, faces, edges)
}

#[test]
fn box_faces_are_planes_with_outward_normals() {
    let (m, idx, faces, _) = box_model();
    let outward = [-Vec3::Z, Vec3::Z, -Vec3::Y, Vec3::Y, -Vec3::X, Vec3::X];
    for ((&f, n), name) in faces.iter().zip(outward).zip(BOX_FACES) {
        let p = face_properties(&m, f).unwrap();
        assert_eq!(p.kind, SurfaceKind::Plane, "{name}");
        assert_eq!(p.reversed, name == "+y", "{name}");
        let normal = p.plane.unwrap().normal;
        assert!((normal - n).length() < 1e-12, "{name}: {normal}");
        assert_eq!(radius_of(&m, f), None);
        assert_eq!(idx.part_name(&m, f), Some("cube"));
        assert_eq!(p.kind, SurfaceKind::Plane);
    }
}

#[test]
fn adjacent_box_faces_meet_at_right_angles() {
    let (m, _, faces, _) = box_model();
    for i in 0..6 {
        for j in 0..6 {
            let a = angle_between_faces(&m, faces[i], faces[j]).unwrap();
            let (ni, nj) = (BOX_FACES[i], BOX_FACES[j]);
            if i == j {
                assert_eq!(a.between_normals, 0.0);
            } else if ni[1..] == nj[1..] {
                // Opposite faces: antiparallel normals, the box's size apart.
                assert!(close(a.between_normals, PI, 1e-15), "{ni} {nj}");
                assert_eq!(a.between_planes, 0.0);
                assert_eq!(a.interior, None);
                let size = [("z", 30.0), ("y", 20.0), ("x", 10.0)];
                let want = size.iter().find(|(k, _)| *k == &ni[1..]).unwrap().1;
                assert!(close(a.distance.unwrap(), want, 1e-12), "{ni} {nj}");
            } else {
                assert!(close(a.between_normals, FRAC_PI_2, 1e-15), "{ni} {nj}");
                assert!(close(a.interior.unwrap(), FRAC_PI_2, 1e-15), "{ni} {nj}");
                assert!(a.shared_edge.is_some() && a.distance.is_none());
            }
        }
    }
}

#[test]
fn box_edges_are_lines_of_the_box_lengths() {
    let (m, idx, _, edges) = box_model();
    assert_eq!(edges.len(), 12);
    for &((a, b), e) in &edges {
        let p = edge_properties(&m, e).unwrap();
        assert_eq!(p.kind, CurveKind::Line);
        let want = [10.0, 20.0, 30.0][(a ^ b).trailing_zeros() as usize];
        assert!(
            close(p.length.unwrap(), want, 1e-12),
            "{a}-{b}: {:?}",
            p.length
        );
        assert!(close((p.end - p.start).length(), want, 1e-12));
        let d = p.direction.unwrap();
        assert!((d - (p.end - p.start) / want).length() < 1e-12);
        let (s, t) = (m.edges[e.index()].start, m.edges[e.index()].end);
        assert!(close(vertex_distance(&m, s, t).unwrap(), want, 1e-12));
        assert_eq!(
            idx.entity(m.edges[e.index()].step_id),
            Some(Entity::Edge(e))
        );
        assert_eq!(radius_of(&m, e), None);
    }
}

/// Cylinder r 5, h 10: side #56 bounded by circles #40 (z 0) and #41 (z 10), bottom #63 and
/// top #67 planes.
const CYLINDER: &str = "
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5=CARTESIAN_POINT('',(0.,0.,10.));#6=AXIS2_PLACEMENT_3D('',#5,#2,#3);
#10=CYLINDRICAL_SURFACE('',#4,5.);#11=PLANE('',#4);#12=PLANE('',#6);
#20=CIRCLE('',#4,5.);#21=CIRCLE('',#6,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#32=CARTESIAN_POINT('',(5.,0.,10.));#33=VERTEX_POINT('',#32);
#40=EDGE_CURVE('',#31,#31,#20,.T.);#41=EDGE_CURVE('',#33,#33,#21,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.T.);#51=EDGE_LOOP('',(#50));#52=FACE_BOUND('',#51,.T.);
#53=ORIENTED_EDGE('',*,*,#41,.F.);#54=EDGE_LOOP('',(#53));#55=FACE_BOUND('',#54,.T.);
#56=ADVANCED_FACE('side',(#52,#55),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#40,.F.);#61=EDGE_LOOP('',(#60));#62=FACE_OUTER_BOUND('',#61,.T.);
#63=ADVANCED_FACE('bottom',(#62),#11,.F.);
#64=ORIENTED_EDGE('',*,*,#41,.T.);#65=EDGE_LOOP('',(#64));#66=FACE_OUTER_BOUND('',#65,.T.);
#67=ADVANCED_FACE('top',(#66),#12,.T.);
#90=CLOSED_SHELL('',(#56,#63,#67));#100=MANIFOLD_SOLID_BREP('',#90);
";

#[test]
fn cylinder_radius_circle_length_and_parallel_caps() {
    let m = model(
        CYLINDER,
        "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#100),#900)",
    );
    let idx = StepIndex::new(&m);
    let side = idx.face(56).unwrap();
    let p = face_properties(&m, side).unwrap();
    assert_eq!((p.kind, p.radius), (SurfaceKind::Cylinder, Some(5.0)));
    assert_eq!(p.axis.unwrap().direction, Vec3::Z);
    assert_eq!(p.plane, None);
    assert_eq!(radius_of(&m, side), Some(5.0));

    let circle = idx.edge(40).unwrap();
    let e = edge_properties(&m, circle).unwrap();
    assert_eq!(e.kind, CurveKind::Circle);
    assert!(e.closed);
    let len = e.length.unwrap();
    assert!(close(len, 10.0 * PI, 1e-9), "{len}");
    assert_eq!(e.radius, Some(5.0));
    assert_eq!(e.centre, Some(Vec3::ZERO));
    assert_eq!(radius_of(&m, circle), Some(5.0));

    let (bottom, top) = (idx.face(63).unwrap(), idx.face(67).unwrap());
    let a = angle_between_faces(&m, bottom, top).unwrap();
    assert!((a.normal_a + Vec3::Z).length() < 1e-15 && (a.normal_b - Vec3::Z).length() < 1e-15);
    assert!(close(a.between_normals, PI, 1e-15));
    assert_eq!(a.distance, Some(10.0));
    assert_eq!(angle_between_faces(&m, bottom, side), None);
}

#[test]
fn bspline_edge_length_matches_a_fine_polyline() {
    let data = "
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#10=PLANE('',#4);
#11=CARTESIAN_POINT('',(2.,5.,0.));#12=CARTESIAN_POINT('',(5.,-3.,0.));
#13=CARTESIAN_POINT('',(8.,4.,0.));#14=CARTESIAN_POINT('',(10.,0.,0.));
#15=CARTESIAN_POINT('',(6.,7.,0.));
#20=B_SPLINE_CURVE_WITH_KNOTS('',3,(#1,#11,#15,#12,#13,#14),.UNSPECIFIED.,.F.,.F.,(4,1,1,4),
 (0.,0.3,0.5,1.),.UNSPECIFIED.);
#21=DIRECTION('',(-1.,0.,0.));#22=VECTOR('',#21,10.);#23=LINE('',#14,#22);
#30=VERTEX_POINT('',#1);#31=VERTEX_POINT('',#14);
#40=EDGE_CURVE('',#30,#31,#20,.T.);#41=EDGE_CURVE('',#31,#30,#23,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.T.);#51=ORIENTED_EDGE('',*,*,#41,.T.);
#52=EDGE_LOOP('',(#50,#51));#53=FACE_OUTER_BOUND('',#52,.T.);
#54=ADVANCED_FACE('',(#53),#10,.T.);
#60=OPEN_SHELL('',(#54));#61=SHELL_BASED_SURFACE_MODEL('',(#60));
";
    let m = model(
        data,
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('sheet',(#61),#900)",
    );
    let idx = StepIndex::new(&m);
    let e = idx.edge(40).unwrap();
    let p = edge_properties(&m, e).unwrap();
    assert_eq!(p.kind, CurveKind::BSpline);
    let (t0, t1) = p.range.unwrap();
    assert!(t0.abs() < 1e-9 && (t1 - 1.0).abs() < 1e-9, "{t0} {t1}");
    let curve = &m.curves[m.edges[e.index()].curve.unwrap().index()];
    let n = 200_000;
    let poly: f64 = (0..n)
        .map(|i| {
            let t = |k: usize| t0 + (t1 - t0) * k as f64 / n as f64;
            (curve.eval(t(i + 1)) - curve.eval(t(i))).length()
        })
        .sum();
    let len = p.length.unwrap();
    // The chords fall short by O(1/n²): a few 1e-10 here.
    assert!(len >= poly && (len - poly) / len < 1e-8, "{len} vs {poly}");
    assert!(len > 10.0, "longer than its chord");
    assert_eq!(idx.part_name(&m, e), Some("sheet"));
    // The closing line.
    let line = edge_properties(&m, idx.edge(41).unwrap()).unwrap();
    assert!(close(line.length.unwrap(), 10.0, 1e-12));
    assert_eq!(line.direction, Some(-Vec3::X));
}

/// B-spline faces and edges of the corpus found to be cylinders, spheres and circles: the
/// I-DEAS file's bore (#435, a rational B-spline of radius 18) among them; every radius
/// found is positive and finite. Skipped without `../shared`.
#[test]
fn corpus_bsplines_that_are_round_get_their_radius() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/step");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!(
            "skipping: {} not found (clone without the shared data)",
            dir.display()
        );
        return;
    };
    let mut files: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    let (mut faces, mut round_faces, mut edges, mut circles) = (0, 0, 0, 0);
    let mut bore = None;
    for path in files {
        let Ok(bytes) = std::fs::read(&path) else {
            continue;
        };
        let Ok(file) = StepFile::parse(bytes) else {
            continue;
        };
        let model = cadre_step::map_file(&file);
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        for k in 0..model.faces.len() {
            let Some(p) = face_properties(&model, FaceId(k as u32)) else {
                continue;
            };
            if p.kind != SurfaceKind::BSpline {
                continue;
            }
            faces += 1;
            if let Some((_, deviation)) = p.recognised {
                round_faces += 1;
                let r = p.radius.expect("a radius");
                assert!(
                    r > 0.0 && r.is_finite() && deviation.is_finite(),
                    "{name}: {p:?}"
                );
            }
            if name == "trj9_io1-id-214.stp" && p.step_id == 435 {
                bore = Some(p);
            }
        }
        for k in 0..model.edges.len() {
            let Some(p) = edge_properties(&model, EdgeId(k as u32)) else {
                continue;
            };
            if p.kind == CurveKind::BSpline {
                edges += 1;
                circles += usize::from(p.recognised.is_some());
            }
        }
    }
    eprintln!(
        "B-spline faces found round: {round_faces} of {faces}; B-spline edges found circles: \
         {circles} of {edges}"
    );
    let bore = bore.expect("trj9_io1-id-214.stp's face #435");
    assert_eq!(bore.recognised.map(|r| r.0), Some("cylinder"));
    assert!(close(bore.radius.unwrap(), 18.0, 1e-9), "{bore:?}");
    assert!(bore.axis.unwrap().direction.cross(Vec3::X).length() < 1e-9);
    assert!(round_faces > 0 && circles > 0);
}
