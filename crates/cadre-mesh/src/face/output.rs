//! Assembly of the [`FaceMesh`]: inside triangles in the face's orientation, degenerate
//! (welded) triangles dropped, and normals, with a fallback at singular points.

use cadre_geom::{Surface, Vec3};
use spade::Triangulation;

use super::cdt::Cdt;
use super::{FaceMesh, MeshPoint, Points};

/// Builds the output mesh from the final triangulation and its face classification;
/// `repaired` says whether the trim loops needed repair.
pub(crate) fn assemble(
    surface: &Surface,
    reversed: bool,
    cdt: &Cdt,
    pts: &Points,
    inside: &[bool],
    truncated: bool,
    repaired: bool,
) -> FaceMesh {
    let ids: Vec<usize> = cdt.vertices().map(|v| v.data().id as usize).collect();
    let triangles: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| inside[f.fix().index()])
        .map(|f| f.vertices().map(|v| v.data().id as usize))
        .collect();
    assemble_ids(
        surface, reversed, &ids, &triangles, pts, truncated, repaired,
    )
}

/// The face mesh of the points `ids` (indices into `pts`, in output order) and the
/// triangles over them (also indices into `pts`, counter-clockwise in (u, v)): triangles
/// with two corners of one key are left out, triangles and normals flipped for a reversed
/// face, missing normals filled in.
pub(crate) fn assemble_ids(
    surface: &Surface,
    reversed: bool,
    ids: &[usize],
    tris: &[[usize; 3]],
    pts: &Points,
    truncated: bool,
    repaired: bool,
) -> FaceMesh {
    let sign = if reversed { -1.0 } else { 1.0 };

    let mut remap = vec![u32::MAX; pts.len()];
    let mut points = Vec::with_capacity(ids.len());
    let mut missing = false;
    for &id in ids {
        remap[id] = points.len() as u32;
        let normal = pts.normal[id].map_or(Vec3::ZERO, |n| n * sign);
        missing |= pts.normal[id].is_none();
        points.push(MeshPoint {
            uv: pts.uv[id],
            xyz: pts.xyz[id],
            normal,
            key: pts.key[id],
        });
    }

    let mut triangles = Vec::with_capacity(tris.len());
    for &ids in tris {
        let keys = ids.map(|i| pts.key[i]);
        // Two corners welded to one vertex: the triangle has no area in 3D.
        if (0..3).any(|i| keys[i].is_some() && keys[i] == keys[(i + 1) % 3]) {
            continue;
        }
        let [a, b, c] = ids.map(|i| remap[i]);
        // Counter-clockwise in (u, v) faces along ∂S/∂u × ∂S/∂v.
        triangles.push(if reversed { [a, c, b] } else { [a, b, c] });
    }

    if missing {
        fill_singular_normals(surface, sign, &mut points, &triangles);
    }
    FaceMesh {
        points,
        triangles,
        truncated,
        repaired,
    }
}

/// Where the surface has no normal (apex, degenerate patch corner) use the area-weighted
/// normal of the triangles around the point; failing that the normal at the centre of the
/// domain, or +z as a last resort so the output stays unit length.
fn fill_singular_normals(
    surface: &Surface,
    sign: f64,
    points: &mut [MeshPoint],
    triangles: &[[u32; 3]],
) {
    let mut acc = vec![Vec3::ZERO; points.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| points[i as usize].xyz);
        let n = (b - a).cross(c - a);
        for &i in t {
            if points[i as usize].normal == Vec3::ZERO {
                acc[i as usize] += n;
            }
        }
    }
    let (mut lo, mut hi) = (points[0].uv, points[0].uv);
    for p in points.iter() {
        lo = lo.min(p.uv);
        hi = hi.max(p.uv);
    }
    let c = 0.5 * (lo + hi);
    let fallback = || surface.normal(c.x, c.y).map_or(Vec3::Z, |n| n * sign);
    let mut fb = None;
    for (p, a) in points.iter_mut().zip(&acc) {
        if p.normal == Vec3::ZERO {
            p.normal = match a.try_normalize() {
                Some(n) => n,
                None => *fb.get_or_insert_with(fallback),
            };
        }
    }
}
