//! Topology: solids, shells, faces, loops, edges, vertices, and the pcurves of edges.
//!
//! Orientation flags are kept as the file gives them. A face whose surface cannot be mapped is
//! dropped with a warning; an edge that cannot be mapped is dropped from its loop with a
//! warning, and the face is kept.

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use super::geometry::{parameter_scale, scale_pcurve};
use cadre_brep::topology::{Edge, Face, Loop, LoopKind, OrientedEdge, Shell, Solid, Vertex};
use cadre_brep::{CurveId, EdgeId, FaceId, PcurveId, ShellId, SolidId, SurfaceId, VertexId};
use cadre_geom::{Frame, Surface, Vec3};

impl Mapper<'_> {
    /// A `MANIFOLD_SOLID_BREP`, `BREP_WITH_VOIDS` or `FACETED_BREP`.
    pub fn solid(&mut self, id: u64) -> MapResult<SolidId> {
        if let Some(&s) = self.solids.get(&self.key(id)) {
            return Ok(s);
        }
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        let outer_id = a.r#ref(1)?;
        let outer = self.nested(id, |m| m.shell(outer_id))?.0;
        if self.model.shells[outer.index()].faces.is_empty() {
            // Counted as a solid, it bounded nothing and said nothing.
            return Err(MapError::new(
                id,
                format!("its outer shell #{outer_id} has no faces; the solid is left out"),
            ));
        }
        let mut voids = Vec::new();
        if inst.has("BREP_WITH_VOIDS") {
            let list = match inst.record("BREP_WITH_VOIDS") {
                Some(rec) if inst.complex => rec.params.first(),
                _ => a.params.get(2),
            };
            for v in list.and_then(|p| p.as_list()).unwrap_or(&[]) {
                let Some(vid) = v.as_ref_id() else { continue };
                match self.nested(id, |m| m.shell(vid)) {
                    Ok((s, _)) => voids.push(s),
                    Err(e) => self.report(&e),
                }
            }
        }
        let sid = SolidId(self.model.solids.len() as u32);
        self.model.solids.push(Solid {
            outer,
            voids,
            step_id: id,
        });
        self.solids.insert(self.key(id), sid);
        Ok(sid)
    }

    /// A shell: `CLOSED_SHELL`, `OPEN_SHELL`, `CONNECTED_FACE_SET`, or an oriented shell
    /// (then a new shell with every face's orientation flipped when reversed). Returns the
    /// shell and whether the file flagged it reversed.
    pub fn shell(&mut self, id: u64) -> MapResult<(ShellId, bool)> {
        if let Some(&s) = self.shells.get(&self.key(id)) {
            return Ok((s, false));
        }
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        let (faces, closed, reversed) = match a.keyword {
            "ORIENTED_CLOSED_SHELL" | "ORIENTED_OPEN_SHELL" => {
                let element = a.r#ref(2)?;
                let forward = a.bool_or(3, true);
                let (base, _) = self.nested(id, |m| m.shell(element))?;
                let base = self.model.shells[base.index()].clone();
                let faces = base.faces.iter().map(|&(f, o)| (f, o == forward)).collect();
                (faces, base.closed, !forward)
            }
            "CLOSED_SHELL" | "OPEN_SHELL" | "CONNECTED_FACE_SET" => {
                let mut faces = Vec::new();
                for f in a.refs(1)? {
                    match self.nested(id, |m| m.oriented_face(f)) {
                        Ok(of) => faces.push(of),
                        Err(e) => self.report(&e),
                    }
                }
                (faces, a.keyword == "CLOSED_SHELL", false)
            }
            other => return Err(a.err(format!("{other} is not a shell"))),
        };
        let sid = ShellId(self.model.shells.len() as u32);
        self.model.shells.push(Shell {
            faces,
            closed,
            step_id: id,
        });
        self.shells.insert(self.key(id), sid);
        Ok((sid, reversed))
    }

    /// A face with the orientation its shell uses it in.
    fn oriented_face(&mut self, id: u64) -> MapResult<(FaceId, bool)> {
        if self.is(id, "ORIENTED_FACE") {
            let inst = self.inst(id)?;
            let a = Attrs::of(&inst, "ORIENTED_FACE")?;
            let element = a.r#ref(2)?;
            let forward = a.bool_or(3, true);
            let (f, o) = self.nested(id, |m| m.oriented_face(element))?;
            return Ok((f, o == forward));
        }
        Ok((self.face(id)?, true))
    }

    /// An `ADVANCED_FACE`, `FACE_SURFACE`, or a bare `FACE` of a faceted B-Rep (its plane is
    /// fitted to the polygon).
    pub fn face(&mut self, id: u64) -> MapResult<FaceId> {
        if let Some(&f) = self.faces.get(&self.key(id)) {
            return Ok(f);
        }
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        if !matches!(a.keyword, "ADVANCED_FACE" | "FACE_SURFACE" | "FACE") {
            return Err(a.err(format!("{} is not a face", a.keyword)));
        }
        let mut loops = Vec::new();
        for b in a.refs(1)? {
            match self.nested(id, |m| m.face_bound(b)) {
                Ok(l) => loops.push(l),
                Err(e) => self.report(&e),
            }
        }
        let (surface, same_sense) = match a.keyword {
            "FACE" => (self.fitted_plane(id, &loops)?, true),
            _ => {
                let s = a.r#ref(2)?;
                (self.nested(id, |m| m.surface_id(s))?, a.bool_or(3, true))
            }
        };
        let fid = FaceId(self.model.faces.len() as u32);
        self.model.faces.push(Face {
            surface,
            same_sense,
            loops,
            step_id: id,
        });
        self.faces.insert(self.key(id), fid);
        Ok(fid)
    }

    /// A plane through a polygon (Newell's normal), for faces that have no surface.
    fn fitted_plane(&mut self, id: u64, loops: &[Loop]) -> MapResult<SurfaceId> {
        let pts: Vec<Vec3> = loops
            .iter()
            .flat_map(|l| match &l.kind {
                LoopKind::Poly(p) => p.clone(),
                LoopKind::Edges(es) => es
                    .iter()
                    .map(|oe| {
                        let e = &self.model.edges[oe.edge.index()];
                        self.model.vertices[e.start.index()].point
                    })
                    .collect(),
                LoopKind::Vertex(v) => vec![self.model.vertices[v.index()].point],
            })
            .collect();
        let mut normal = Vec3::ZERO;
        for (i, p) in pts.iter().enumerate() {
            let q = pts[(i + 1) % pts.len()];
            normal += Vec3::new(
                (p.y - q.y) * (p.z + q.z),
                (p.z - q.z) * (p.x + q.x),
                (p.x - q.x) * (p.y + q.y),
            );
        }
        let centre = pts.iter().copied().sum::<Vec3>() / pts.len().max(1) as f64;
        let frame = Frame::from_axis(centre, normal, None)
            .ok_or_else(|| MapError::new(id, "face polygon is degenerate (no plane)"))?;
        let sid = SurfaceId(self.model.surfaces.len() as u32);
        self.model.surfaces.push(Surface::Plane { frame });
        Ok(sid)
    }

    /// A `FACE_BOUND` / `FACE_OUTER_BOUND`.
    fn face_bound(&mut self, id: u64) -> MapResult<Loop> {
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        if !matches!(a.keyword, "FACE_BOUND" | "FACE_OUTER_BOUND") {
            return Err(a.err(format!("{} is not a face bound", a.keyword)));
        }
        let loop_id = a.r#ref(1)?;
        let orientation = a.bool_or(2, true);
        let kind = self.nested(id, |m| m.loop_kind(loop_id))?;
        Ok(Loop {
            kind,
            orientation,
            outer: a.keyword == "FACE_OUTER_BOUND",
        })
    }

    fn loop_kind(&mut self, id: u64) -> MapResult<LoopKind> {
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        match a.keyword {
            "EDGE_LOOP" => {
                let mut edges = Vec::new();
                for oe in a.refs(1)? {
                    match self.nested(id, |m| m.oriented_edge(oe)) {
                        Ok(e) => edges.push(e),
                        Err(e) => self.report(&e),
                    }
                }
                Ok(LoopKind::Edges(edges))
            }
            "VERTEX_LOOP" => Ok(LoopKind::Vertex(self.vertex(a.r#ref(1)?)?)),
            "POLY_LOOP" => {
                let pts = a
                    .refs(1)?
                    .into_iter()
                    .map(|p| self.point3(p))
                    .collect::<MapResult<Vec<_>>>()?;
                if pts.len() < 3 {
                    return Err(a.err("poly loop needs at least three points"));
                }
                Ok(LoopKind::Poly(pts))
            }
            other => Err(a.err(format!("{other} is not a loop"))),
        }
    }

    fn oriented_edge(&mut self, id: u64) -> MapResult<OrientedEdge> {
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        match a.keyword {
            "ORIENTED_EDGE" => {
                let element = a.r#ref(3)?;
                let forward = a.bool_or(4, true);
                let inner = self.nested(id, |m| m.oriented_edge(element))?;
                Ok(OrientedEdge {
                    edge: inner.edge,
                    forward: inner.forward == forward,
                })
            }
            "EDGE_CURVE" => Ok(OrientedEdge {
                edge: self.edge(id)?,
                forward: true,
            }),
            other => Err(a.err(format!("{other} is not an edge"))),
        }
    }

    /// An `EDGE_CURVE` with its 3D curve and the pcurves the file gives.
    pub fn edge(&mut self, id: u64) -> MapResult<EdgeId> {
        if let Some(&e) = self.edges.get(&self.key(id)) {
            return Ok(e);
        }
        let inst = self.inst(id)?;
        let a = Attrs::of(&inst, "EDGE_CURVE")?;
        let start = self.vertex(a.r#ref(1)?)?;
        let end = self.vertex(a.r#ref(2)?)?;
        let geometry = a.r#ref(3)?;
        let same_sense = a.bool_or(4, true);
        let mut pcurves = Vec::new();
        let curve = if self.is(geometry, "PCURVE") {
            // Only a curve on a surface: keep it as a pcurve, no 3D curve.
            match self.nested(id, |m| m.pcurve(geometry)) {
                Ok(p) => pcurves.push(p),
                Err(e) => self.report(&e),
            }
            None
        } else {
            self.collect_pcurves(geometry, &mut pcurves);
            match self.nested(id, |m| m.curve_id(geometry)) {
                Ok(c) => Some(c),
                Err(e) => {
                    self.report(&e);
                    None
                }
            }
        };
        let curve = curve.map(|c| self.heal_line(id, c, start, end, same_sense));
        let eid = EdgeId(self.model.edges.len() as u32);
        self.model.edges.push(Edge {
            curve,
            start,
            end,
            same_sense,
            pcurves,
            step_id: id,
        });
        self.edges.insert(self.key(id), eid);
        Ok(eid)
    }

    /// A straight edge whose line misses its own vertices (beyond 100 × the context's
    /// uncertainty, at least 1 µm) is given the line through them instead, with a warning:
    /// the vertices are what the neighbouring faces share.
    fn heal_line(
        &mut self,
        edge: u64,
        curve: cadre_brep::CurveId,
        start: VertexId,
        end: VertexId,
        same_sense: bool,
    ) -> cadre_brep::CurveId {
        let cadre_geom::Curve3::Line { origin, direction } = self.model.curves[curve.index()]
        else {
            return curve;
        };
        let (a, b) = (
            self.model.vertices[start.index()].point,
            self.model.vertices[end.index()].point,
        );
        let Some(unit) = direction.try_normalize() else {
            return curve;
        };
        let off = |p: Vec3| (p - origin - unit * (p - origin).dot(unit)).length();
        let miss = off(a).max(off(b));
        let tol = (self.units.uncertainty_mm.unwrap_or(1e-7) * 100.0).max(1e-3);
        if miss <= tol || (b - a).length() <= tol {
            return curve;
        }
        self.warn(
            edge,
            format!(
                "edge's line misses its vertices by {miss:.4} mm; the segment between them is used"
            ),
        );
        let (from, to) = if same_sense { (a, b) } else { (b, a) };
        let healed = CurveId(self.model.curves.len() as u32);
        self.model.curves.push(cadre_geom::Curve3::Line {
            origin: from,
            direction: to - from,
        });
        healed
    }

    /// The pcurves listed by a `SURFACE_CURVE` / `SEAM_CURVE` (associated geometry).
    fn collect_pcurves(&mut self, geometry: u64, out: &mut Vec<(SurfaceId, PcurveId)>) {
        let Ok(inst) = self.inst(geometry) else {
            return;
        };
        let Some(rec) = inst.records.iter().find(|r| {
            matches!(
                r.keyword,
                "SURFACE_CURVE" | "SEAM_CURVE" | "INTERSECTION_CURVE" | "BOUNDED_SURFACE_CURVE"
            )
        }) else {
            return;
        };
        // Simple instances start with the name; complex ones keep it in another record.
        let o = usize::from(!inst.complex);
        let assoc: Vec<u64> = rec
            .params
            .get(o + 1)
            .and_then(|p| p.as_list())
            .unwrap_or(&[])
            .iter()
            .filter_map(|p| p.as_ref_id())
            .collect();
        for p in assoc {
            if !self.is(p, "PCURVE") {
                continue;
            }
            match self.nested(geometry, |m| m.pcurve(p)) {
                Ok(pc) => out.push(pc),
                Err(e) => self.report(&e),
            }
        }
    }

    /// A `PCURVE`: its surface and its 2D curve in that surface's (mm, radian) parameters.
    fn pcurve(&mut self, id: u64) -> MapResult<(SurfaceId, PcurveId)> {
        if let Some(&p) = self.pcurves.get(&self.key(id)) {
            return Ok(p);
        }
        let inst = self.inst(id)?;
        let a = Attrs::of(&inst, "PCURVE")?;
        let surface = self.surface_id(a.r#ref(1)?)?;
        let rep = self.inst(a.r#ref(2)?)?;
        // A complex definitional representation keeps (name, items, context) in its
        // REPRESENTATION record (its first record, DEFINITIONAL_REPRESENTATION(), is empty).
        let r = Attrs::of(&rep, "REPRESENTATION").or_else(|_| Attrs::first(&rep))?;
        let curve_id = r
            .refs(1)?
            .into_iter()
            .next()
            .ok_or_else(|| r.err("definitional representation has no curve"))?;
        let raw = self.curve2(curve_id)?;
        let (su, sv) = parameter_scale(&self.model.surfaces[surface.index()], &self.units);
        let curve = scale_pcurve(raw, su, sv).ok_or_else(|| {
            a.err("pcurve is a conic in a space with mixed length/angle units; not scaled")
        })?;
        let pid = PcurveId(self.model.pcurves.len() as u32);
        self.model.pcurves.push(curve);
        self.pcurves.insert(self.key(id), (surface, pid));
        Ok((surface, pid))
    }

    /// A `VERTEX_POINT`.
    pub fn vertex(&mut self, id: u64) -> MapResult<VertexId> {
        if let Some(&v) = self.vertices.get(&self.key(id)) {
            return Ok(v);
        }
        let inst = self.inst(id)?;
        let a = Attrs::of(&inst, "VERTEX_POINT")?;
        let p = a.r#ref(1)?;
        let point = if self.is(p, "CARTESIAN_POINT") {
            self.point3(p)?
        } else {
            return Err(a.err("vertex geometry is not a cartesian point"));
        };
        let vid = VertexId(self.model.vertices.len() as u32);
        self.model.vertices.push(Vertex { point, step_id: id });
        self.vertices.insert(self.key(id), vid);
        Ok(vid)
    }
}

/// Keywords of surfaces that can stand alone in a geometric set (each becomes a face).
pub const SURFACE_KEYWORDS: &[&str] = &[
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
    "B_SPLINE_SURFACE",
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "BEZIER_SURFACE",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
    "RECTANGULAR_TRIMMED_SURFACE",
    "CURVE_BOUNDED_SURFACE",
];

impl Mapper<'_> {
    /// A surface placed alone (in a geometric set) as a face: its own domain, or for a
    /// `CURVE_BOUNDED_SURFACE` the region its boundary curves enclose, as edge loops.
    pub fn surface_face(&mut self, id: u64) -> MapResult<FaceId> {
        if let Some(&f) = self.faces.get(&self.key(id)) {
            return Ok(f);
        }
        let surface = self.surface_id(id)?;
        let bounded_by_curves = self.is(id, "CURVE_BOUNDED_SURFACE");
        let s = &self.model.surfaces[surface.index()];
        let ((u0, u1), (v0, v1)) = s.domain();
        if !bounded_by_curves && (!(u1 - u0).is_finite() || !(v1 - v0).is_finite()) {
            // An unbounded surface alone in a set is construction geometry (a datum plane):
            // it has no extent to draw, and CAD kernels make no face of it (tr8_ha1_db.stp).
            return Err(MapError::new(
                id,
                format!(
                    "unbounded {} placed alone in a set is construction geometry: no face made",
                    s.type_name().to_lowercase()
                ),
            ));
        }
        let mut loops = Vec::new();
        if bounded_by_curves {
            let inst = self.inst(id)?;
            let a = Attrs::first(&inst)?;
            for b in a.refs(2)? {
                match self.nested(id, |m| m.boundary_loop(b, surface)) {
                    Ok(l) => loops.push(l),
                    Err(e) => self.report(&e),
                }
            }
        }
        let mut regions = split_disjoint_boundaries(&self.model, surface, loops).into_iter();
        let mut face_ids = Vec::new();
        let first = regions.next().unwrap_or_default();
        for loops in std::iter::once(first).chain(regions) {
            let fid = FaceId(self.model.faces.len() as u32);
            self.model.faces.push(Face {
                surface,
                same_sense: true,
                loops,
                step_id: id,
            });
            face_ids.push(fid);
        }
        if face_ids.len() > 1 {
            self.extra_faces.insert(face_ids[0], face_ids[1..].to_vec());
        }
        self.faces.insert(self.key(id), face_ids[0]);
        Ok(face_ids[0])
    }

    /// A `BOUNDARY_CURVE` / `OUTER_BOUNDARY_CURVE` as a loop of edges, one per segment, with
    /// vertices at the segments' ends.
    fn boundary_loop(&mut self, id: u64, surface: SurfaceId) -> MapResult<Loop> {
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        let outer = a.keyword == "OUTER_BOUNDARY_CURVE";
        let mut edges = Vec::new();
        for seg in a.refs(1)? {
            let s_inst = self.inst(seg)?;
            let s = Attrs::of(&s_inst, "COMPOSITE_CURVE_SEGMENT")?;
            let same_sense = s.bool_or(1, true);
            let parent = s.r#ref(2)?;
            let mut pcurves = Vec::new();
            let curve = if self.is(parent, "PCURVE") {
                pcurves.push(self.nested(seg, |m| m.pcurve(parent))?);
                None
            } else {
                self.collect_pcurves(parent, &mut pcurves);
                Some(self.nested(seg, |m| m.curve_id(parent))?)
            };
            let (p0, p1) = self.segment_ends(curve, &pcurves, surface).ok_or_else(|| {
                MapError::new(
                    seg,
                    "boundary segment has no bounded curve to take ends from",
                )
            })?;
            let start = self.new_vertex(p0);
            let end = self.new_vertex(p1);
            let eid = EdgeId(self.model.edges.len() as u32);
            self.model.edges.push(Edge {
                curve,
                start,
                end,
                same_sense: true,
                pcurves,
                step_id: seg,
            });
            edges.push(OrientedEdge {
                edge: eid,
                forward: same_sense,
            });
        }
        Ok(Loop {
            kind: LoopKind::Edges(edges),
            orientation: true,
            outer,
        })
    }

    /// Start and end points of a bounded curve, or of a pcurve evaluated on its surface.
    fn segment_ends(
        &self,
        curve: Option<cadre_brep::CurveId>,
        pcurves: &[(SurfaceId, PcurveId)],
        surface: SurfaceId,
    ) -> Option<(Vec3, Vec3)> {
        if let Some(c) = curve {
            let c = &self.model.curves[c.index()];
            let (t0, t1) = c.start_end_params()?;
            return Some((c.eval(t0), c.eval(t1)));
        }
        let &(s, p) = pcurves
            .iter()
            .find(|(s, _)| *s == surface)
            .or(pcurves.first())?;
        let pc = &self.model.pcurves[p.index()];
        let (t0, t1) = pc.start_end_params()?;
        let s = &self.model.surfaces[s.index()];
        let (a, b) = (pc.eval(t0), pc.eval(t1));
        Some((s.eval(a.x, a.y), s.eval(b.x, b.y)))
    }

    fn new_vertex(&mut self, point: Vec3) -> VertexId {
        let vid = VertexId(self.model.vertices.len() as u32);
        self.model.vertices.push(Vertex { point, step_id: 0 });
        vid
    }
}

/// Groups the boundaries of a curve-bounded surface into regions: each boundary not inside
/// another (in the surface's parameters) starts a region, and takes the boundaries directly
/// inside it as holes. A surface with two disjoint outer boundaries is two faces.
fn split_disjoint_boundaries(
    model: &cadre_brep::Model,
    surface: SurfaceId,
    loops: Vec<Loop>,
) -> Vec<Vec<Loop>> {
    if loops.len() < 2 {
        return vec![loops];
    }
    let acc = cadre_geom::Accuracy::default();
    let s = &model.surfaces[surface.index()];
    let regions: Vec<Option<cadre_brep::bounds::UvRegion>> = loops
        .iter()
        .map(|l| {
            let face = Face {
                surface,
                same_sense: true,
                loops: vec![l.clone()],
                step_id: 0,
            };
            cadre_brep::bounds::face_uv_region(model, &face, s, acc)
                .filter(|r| r.polygons.is_some())
        })
        .collect();
    // A boundary's first (u, v) point, to test containment in the others.
    let first_point = |i: usize| {
        regions[i]
            .as_ref()
            .and_then(|r| r.polygons.as_ref()?.first()?.first().copied())
    };
    let inside = |i: usize, j: usize| -> bool {
        match (first_point(i), regions[j].as_ref()) {
            (Some((u, v)), Some(r)) => r.contains(u, v),
            _ => false,
        }
    };
    if regions.iter().any(Option::is_none) {
        return vec![loops];
    }
    let n = loops.len();
    let depth: Vec<usize> = (0..n)
        .map(|i| (0..n).filter(|&j| j != i && inside(i, j)).count())
        .collect();
    let outers: Vec<usize> = (0..n).filter(|&i| depth[i] == 0).collect();
    if outers.len() < 2 {
        return vec![loops];
    }
    let mut groups: Vec<Vec<Loop>> = outers.iter().map(|&o| vec![loops[o].clone()]).collect();
    for i in (0..n).filter(|&i| depth[i] == 1) {
        if let Some(g) = outers.iter().position(|&o| inside(i, o)) {
            groups[g].push(loops[i].clone());
        }
    }
    groups
}
