//! The world box of a scene, for framing it.

use cadre_mesh::scene::Scene;
use glam::DVec3;

/// The axis-aligned box of every placed mesh of `scene`, wires included (each mesh's local
/// box transformed by its instances), or `None` for a scene with no vertex.
pub fn scene_bounds(scene: &Scene) -> Option<(DVec3, DVec3)> {
    let local: Vec<Option<(DVec3, DVec3)>> = scene
        .meshes
        .iter()
        .map(|m| {
            m.positions.iter().chain(m.lines.iter().flatten()).fold(
                None,
                |acc: Option<(DVec3, DVec3)>, p| {
                    let p = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
                    if !p.is_finite() {
                        return acc;
                    }
                    Some(match acc {
                        None => (p, p),
                        Some((lo, hi)) => (lo.min(p), hi.max(p)),
                    })
                },
            )
        })
        .collect();
    let mut out: Option<(DVec3, DVec3)> = None;
    for (node, world) in scene.instances() {
        let Some(Some((lo, hi))) = scene.nodes[node].mesh.and_then(|m| local.get(m)) else {
            continue;
        };
        for i in 0..8 {
            let c = DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let p = world.transform_point3(c);
            out = Some(match out {
                None => (p, p),
                Some((a, b)) => (a.min(p), b.max(p)),
            });
        }
    }
    out
}
