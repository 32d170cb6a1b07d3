//! Occurrence counts of a model, counted the way CAD kernels (OCCT's explorers) count them:
//! every instance of a part counts again.

use std::collections::BTreeMap;

use crate::topology::Shell;
use crate::{Body, Model};

/// Counts over all part instances.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Face occurrences (tessellated faces included).
    pub faces: u64,
    /// Shell occurrences (the shells of solids included).
    pub shells: u64,
    /// Solid occurrences.
    pub solids: u64,
    /// Distinct products (product definitions) in the file.
    pub products: u64,
    /// Part instances that carry geometry.
    pub instances: u64,
    /// Face occurrences by support surface type (`"Plane"`, `"Cylinder"`, …,
    /// `"Triangulation"` for tessellated faces).
    pub surface_types: BTreeMap<String, u64>,
}

impl Model {
    /// Counts every face, shell and solid once per instance of the part that owns it.
    pub fn counts(&self) -> Counts {
        let mut c = Counts {
            products: self.parts.iter().filter(|p| p.is_product).count() as u64,
            ..Counts::default()
        };
        self.visit_instances(|visit| {
            let part = self.part(visit.part);
            if !part.bodies.is_empty() {
                c.instances += 1;
            }
            for body in &part.bodies {
                match body {
                    Body::Solid(id) => {
                        c.solids += 1;
                        for shell in self.solids[id.index()].shells() {
                            self.count_shell(&self.shells[shell.index()], &mut c);
                        }
                    }
                    Body::Shell(id) => self.count_shell(&self.shells[id.index()], &mut c),
                    Body::Face(id) => self.count_face(*id, &mut c),
                    Body::Mesh(id) => {
                        let mesh = &self.meshes[id.index()];
                        c.faces += u64::from(mesh.face_count);
                        *c.surface_types.entry("Triangulation".into()).or_default() +=
                            u64::from(mesh.face_count);
                        c.shells += u64::from(mesh.shell_count);
                        c.solids += u64::from(mesh.solid_count);
                    }
                    Body::Edge(_) | Body::Wire(_) | Body::Point(_) => {}
                }
            }
        });
        c
    }

    fn count_shell(&self, shell: &Shell, c: &mut Counts) {
        c.shells += 1;
        for &(face, _) in &shell.faces {
            self.count_face(face, c);
        }
    }

    fn count_face(&self, face: crate::FaceId, c: &mut Counts) {
        c.faces += 1;
        let surface = &self.surfaces[self.faces[face.index()].surface.index()];
        *c.surface_types
            .entry(crate::bounds::reported_type(surface).into())
            .or_default() += 1;
    }
}
