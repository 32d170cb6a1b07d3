//! AP242 tessellated geometry: triangulated faces, surface sets, tessellated shells and solids,
//! kept as triangle meshes (one mesh per tessellated item, faces kept as triangle ranges).

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use crate::syntax::Param;
use cadre_brep::{MeshId, TriangleMesh};
use cadre_geom::Vec3;

/// Tessellated items with more points or triangles than this are refused as corrupt.
const MAX_MESH_ELEMENTS: usize = 1 << 26;

/// Appends one triangulated face or surface set to `mesh`.
struct FaceAppender<'m> {
    mesh: &'m mut TriangleMesh,
}

impl FaceAppender<'_> {
    fn add(&mut self, m: &Mapper<'_>, id: u64) -> MapResult<()> {
        let inst = m.inst(id)?;
        let a = Attrs::first(&inst)?;
        // Surface sets lack the geometric_link attribute that faces have.
        let (is_face, complex) = match a.keyword {
            "TRIANGULATED_FACE" => (true, false),
            "COMPLEX_TRIANGULATED_FACE" => (true, true),
            "TRIANGULATED_SURFACE_SET" => (false, false),
            "COMPLEX_TRIANGULATED_SURFACE_SET" => (false, true),
            other => return Err(a.err(format!("{other} is not a tessellated face"))),
        };
        let coords = coordinates(m, a.r#ref(1)?)?;
        let normals_param = a.list(3)?;
        let pn = if is_face { 5 } else { 4 };
        let pnindex: Vec<usize> = index_list(&a, a.list(pn)?, pn)?;
        let base = self.mesh.positions.len() as u32;
        // Local vertex k of this face is coordinate pnindex[k] (or k when pnindex is empty).
        let local: Vec<Vec3> = if pnindex.is_empty() {
            coords.to_vec()
        } else {
            pnindex
                .iter()
                .map(|&i| {
                    coords
                        .get(i.wrapping_sub(1))
                        .copied()
                        .ok_or_else(|| a.err(format!("point index {i} out of range")))
                })
                .collect::<MapResult<_>>()?
        };
        let normals: Vec<Vec3> = normals_param
            .iter()
            .filter_map(|n| {
                let c = n.as_list()?;
                let v: Vec<f64> = c.iter().filter_map(Param::as_f64).collect();
                (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
            })
            .collect();
        let count = local.len();
        self.mesh.positions.extend_from_slice(&local);
        let keep_normals = self.mesh.normals.len() + count == self.mesh.positions.len()
            && (normals.len() == 1 || normals.len() == count);
        if keep_normals {
            if normals.len() == 1 {
                self.mesh
                    .normals
                    .extend(std::iter::repeat_n(normals[0], count));
            } else {
                self.mesh.normals.extend_from_slice(&normals);
            }
        } else {
            self.mesh.normals.clear();
        }
        let tri = |i: usize, j: usize, k: usize| -> Option<[u32; 3]> {
            let ok = |x: usize| x >= 1 && x <= count;
            (ok(i) && ok(j) && ok(k) && i != j && j != k && i != k).then(|| {
                [
                    base + i as u32 - 1,
                    base + j as u32 - 1,
                    base + k as u32 - 1,
                ]
            })
        };
        self.mesh.face_starts.push(self.mesh.triangles.len() as u32);
        if complex {
            let (strips_i, fans_i) = if is_face { (6, 7) } else { (5, 6) };
            for strip in a.list(strips_i)? {
                let s = index_list(&a, strip.as_list().unwrap_or(&[]), strips_i)?;
                for k in 0..s.len().saturating_sub(2) {
                    let t = if k % 2 == 0 {
                        tri(s[k], s[k + 1], s[k + 2])
                    } else {
                        tri(s[k + 1], s[k], s[k + 2])
                    };
                    self.mesh.triangles.extend(t);
                }
            }
            for fan in a.params.get(fans_i).and_then(Param::as_list).unwrap_or(&[]) {
                let f = index_list(&a, fan.as_list().unwrap_or(&[]), fans_i)?;
                for k in 1..f.len().saturating_sub(1) {
                    self.mesh.triangles.extend(tri(f[0], f[k], f[k + 1]));
                }
            }
        } else {
            let ti = if is_face { 6 } else { 5 };
            for t in a.list(ti)? {
                let t = index_list(&a, t.as_list().unwrap_or(&[]), ti)?;
                if let [i, j, k] = t[..] {
                    self.mesh.triangles.extend(tri(i, j, k));
                }
            }
        }
        if self.mesh.triangles.len() > MAX_MESH_ELEMENTS {
            return Err(a.err("tessellation is beyond reason"));
        }
        self.mesh.face_count += 1;
        Ok(())
    }
}

/// The triangles of one triangulated face or surface set (an annotation's filled areas).
pub(super) fn triangles(m: &Mapper<'_>, id: u64) -> MapResult<TriangleMesh> {
    let mut mesh = TriangleMesh::default();
    FaceAppender { mesh: &mut mesh }.add(m, id)?;
    Ok(mesh)
}

fn index_list(a: &Attrs<'_, '_>, items: &[Param<'_>], i: usize) -> MapResult<Vec<usize>> {
    if items.len() > MAX_MESH_ELEMENTS {
        return Err(a.err("index list is beyond reason"));
    }
    items
        .iter()
        .map(|p| {
            p.as_i64()
                .and_then(|v| usize::try_from(v).ok())
                .ok_or_else(|| a.err(format!("parameter {} holds a bad index", i + 1)))
        })
        .collect()
}

/// A `COORDINATES_LIST` in mm, decoded once per mapping.
pub(super) fn coordinates(m: &Mapper<'_>, id: u64) -> MapResult<std::rc::Rc<Vec<Vec3>>> {
    if let Some(c) = m.coordinates.borrow().get(&m.key(id)) {
        return Ok(c.clone());
    }
    let list = std::rc::Rc::new(decode_coordinates(m, id)?);
    m.coordinates.borrow_mut().insert(m.key(id), list.clone());
    Ok(list)
}

fn decode_coordinates(m: &Mapper<'_>, id: u64) -> MapResult<Vec<Vec3>> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "COORDINATES_LIST")?;
    let l = m.units.length_to_mm;
    let list = a.list(2)?;
    if list.len() > MAX_MESH_ELEMENTS {
        return Err(a.err("coordinate list is beyond reason"));
    }
    list.iter()
        .map(|p| {
            let c = p
                .as_list()
                .ok_or_else(|| a.err("coordinate is not a list"))?;
            let v: Vec<f64> = c.iter().filter_map(Param::as_f64).collect();
            match v[..] {
                [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                    Ok(Vec3::new(x, y, z) * l)
                }
                _ => Err(a.err("coordinate is not three finite numbers")),
            }
        })
        .collect()
}

impl Mapper<'_> {
    /// A `TESSELLATED_SOLID`, `TESSELLATED_SHELL`, or a lone triangulated face / surface set,
    /// as one mesh.
    pub fn tessellated(&mut self, id: u64) -> MapResult<MeshId> {
        if let Some(&m) = self.meshes.get(&self.key(id)) {
            return Ok(m);
        }
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        let mut mesh = TriangleMesh {
            step_id: id,
            ..TriangleMesh::default()
        };
        let items = match a.keyword {
            "TESSELLATED_SOLID" => {
                mesh.solid_count = 1;
                mesh.shell_count = 1;
                a.refs(1)?
            }
            "TESSELLATED_SHELL" => {
                mesh.shell_count = 1;
                a.refs(1)?
            }
            _ => vec![id],
        };
        let mut appender = FaceAppender { mesh: &mut mesh };
        for item in items {
            if let Err(e) = appender.add(self, item) {
                self.report(&e);
            }
        }
        if mesh.face_count == 0 {
            return Err(MapError::new(id, "tessellated item has no usable face"));
        }
        let mid = MeshId(self.model.meshes.len() as u32);
        self.model.meshes.push(mesh);
        self.meshes.insert(self.key(id), mid);
        Ok(mid)
    }
}
