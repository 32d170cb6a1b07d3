//! The model: arenas of geometry and topology, parts, roots, styles and warnings.

use std::collections::HashMap;

use crate::topology::{Edge, Face, Shell, Solid, Vertex};
use crate::{EdgeId, FaceId, MeshId, Part, PartId, ShellId, SolidId, Style, TriangleMesh, Units};
use cadre_geom::{Accuracy, Curve2, Curve3, Surface};

/// A problem met while building the model; the model is still usable.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// STEP instance the problem is about, when there is one.
    pub step_id: Option<u64>,
    /// 1-based line of that instance in the file.
    pub line: Option<u32>,
    /// What is wrong and what was done about it.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.line, self.step_id) {
            (Some(line), Some(id)) => write!(f, "line {line}, #{id}: {}", self.message),
            (None, Some(id)) => write!(f, "#{id}: {}", self.message),
            (Some(line), None) => write!(f, "line {line}: {}", self.message),
            (None, None) => f.write_str(&self.message),
        }
    }
}

/// What a style is attached to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StyleTarget {
    /// A solid.
    Solid(SolidId),
    /// A shell.
    Shell(ShellId),
    /// A face.
    Face(FaceId),
    /// A tessellated item.
    Mesh(MeshId),
    /// An edge.
    Edge(EdgeId),
    /// A whole part.
    Part(PartId),
}

/// A whole model read from a file. Lengths are millimetres and angles radians throughout.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// Support surfaces.
    pub surfaces: Vec<Surface>,
    /// 3D curves of edges and wires.
    pub curves: Vec<Curve3>,
    /// Parameter-space curves of edges on faces, as given by the file.
    pub pcurves: Vec<Curve2>,
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Edges.
    pub edges: Vec<Edge>,
    /// Faces.
    pub faces: Vec<Face>,
    /// Shells.
    pub shells: Vec<Shell>,
    /// Solids.
    pub solids: Vec<Solid>,
    /// Tessellated items.
    pub meshes: Vec<TriangleMesh>,
    /// Parts (products and representations).
    pub parts: Vec<Part>,
    /// Parts not placed by any other part: the tops of the assembly tree.
    pub roots: Vec<PartId>,
    /// Styles by target; a face without one inherits from its shell, solid and part.
    pub styles: HashMap<StyleTarget, Style>,
    /// Units of the main representation context (what the file's geometry was written in).
    pub units: Units,
    /// Schema names from the header (e.g. `AUTOMOTIVE_DESIGN`).
    pub schemas: Vec<String>,
    /// Problems met while reading; each names the instance and line where known.
    pub warnings: Vec<Warning>,
    /// Product manufacturing information: annotations, saved views, semantic PMI.
    pub pmi: crate::pmi::Pmi,
    /// Every edge's parameter range at the default accuracy, worked out on first use of
    /// [`Model::edge_range`] (bounds, edge sampling and closure checks all need them, and
    /// each costs two curve projections). Code that edits vertices, edges or curves after
    /// that calls [`Model::forget_edge_ranges`].
    pub edge_ranges: EdgeRanges,
}

/// The cache behind [`Model::edge_range`].
#[derive(Clone, Debug, Default)]
pub struct EdgeRanges(std::sync::OnceLock<Vec<Option<(f64, f64)>>>);

impl Model {
    /// The parameter interval of edge `id` on its curve ([`crate::bounds::edge_range`]),
    /// cached for the default accuracy: the first call works out every edge's, in parallel.
    pub fn edge_range(&self, id: EdgeId, acc: Accuracy) -> Option<(f64, f64)> {
        if acc != Accuracy::default() {
            return crate::bounds::edge_range(self, self.edges.get(id.index())?, acc);
        }
        let all = self.edge_ranges.0.get_or_init(|| {
            use rayon::prelude::*;
            self.edges
                .par_iter()
                .map(|e| crate::bounds::edge_range(self, e, acc))
                .collect()
        });
        match all.get(id.index()) {
            Some(&range) => range,
            // An edge added after the cache was filled (readers look at bounds while
            // building; they forget the cache when done).
            None => crate::bounds::edge_range(self, self.edges.get(id.index())?, acc),
        }
    }

    /// Drops the cached edge ranges (after vertices, edges or curves changed).
    pub fn forget_edge_ranges(&mut self) {
        self.edge_ranges = EdgeRanges::default();
    }

    /// Works out the cached range of edge `id` again, keeping the others (after one of its
    /// vertices moved).
    pub fn refresh_edge_range(&mut self, id: EdgeId) {
        let acc = Accuracy::default();
        let range = self
            .edges
            .get(id.index())
            .and_then(|e| crate::bounds::edge_range(self, e, acc));
        if let Some(slot) = self
            .edge_ranges
            .0
            .get_mut()
            .and_then(|all| all.get_mut(id.index()))
        {
            *slot = range;
        }
    }
}

impl Model {
    /// The style in force for a face used by `shell` in `solid` of `part`: the most specific
    /// level wins, missing fields come from coarser levels.
    pub fn face_style(
        &self,
        face: FaceId,
        shell: Option<ShellId>,
        solid: Option<SolidId>,
        part: Option<PartId>,
    ) -> Style {
        let levels = [
            Some(StyleTarget::Face(face)),
            shell.map(StyleTarget::Shell),
            solid.map(StyleTarget::Solid),
            part.map(StyleTarget::Part),
        ];
        levels
            .into_iter()
            .flatten()
            .filter_map(|t| self.styles.get(&t))
            .fold(Style::default(), |acc, s| acc.over(*s))
    }

    /// Records a warning.
    pub fn warn(&mut self, step_id: Option<u64>, line: Option<u32>, message: impl Into<String>) {
        self.warnings.push(Warning {
            step_id,
            line,
            message: message.into(),
        });
    }
}
