//! The mapper's state: the file, the model under construction, caches from STEP ids to model
//! ids, the units in force, and a guard against cyclic or absurdly deep references.

use std::collections::{HashMap, HashSet};

use super::error::{MapError, MapResult};
use crate::syntax::{Instance, StepFile};
use cadre_brep::{
    CurveId, EdgeId, FaceId, MeshId, Model, PartId, PcurveId, ShellId, SolidId, SurfaceId, Units,
    VertexId,
};

/// How deep references may nest while mapping one item (offset of offset of trimmed …).
/// Legitimate files stay under a dozen; a cycle hits this bound instead of the stack.
pub const MAX_NESTING: u32 = 64;

/// Cache key: a STEP id mapped under one set of units (a geometric item shared by contexts
/// with different units is mapped once per context).
pub type Key = (u64, u32);

/// Mapper state.
pub struct Mapper<'f> {
    /// The file being mapped.
    pub file: &'f StepFile,
    /// The model being built.
    pub model: Model,
    /// Units in force for the representation being mapped.
    pub units: Units,
    /// Index of `units` among the distinct unit sets met so far (part of cache keys).
    pub units_key: u32,
    /// Distinct unit sets met so far, by context id.
    pub contexts: HashMap<u64, (Units, u32)>,
    /// Nesting depth of the current mapping.
    pub depth: u32,
    /// Mapped surfaces.
    pub surfaces: HashMap<Key, SurfaceId>,
    /// Mapped 3D curves.
    pub curves: HashMap<Key, CurveId>,
    /// Mapped pcurves, by (PCURVE id, units).
    pub pcurves: HashMap<Key, (SurfaceId, PcurveId)>,
    /// Mapped vertices.
    pub vertices: HashMap<Key, VertexId>,
    /// Mapped edges.
    pub edges: HashMap<Key, EdgeId>,
    /// Mapped faces.
    pub faces: HashMap<Key, FaceId>,
    /// Mapped shells.
    pub shells: HashMap<Key, ShellId>,
    /// Mapped solids.
    pub solids: HashMap<Key, SolidId>,
    /// Mapped tessellated items.
    pub meshes: HashMap<Key, MeshId>,
    /// Decoded `COORDINATES_LIST`s: tessellated faces share one list, often a large one, so it
    /// is decoded once rather than once per face.
    pub coordinates: std::cell::RefCell<HashMap<Key, std::rc::Rc<Vec<cadre_geom::Vec3>>>>,
    /// Faces split off a curve-bounded surface with disjoint boundaries, by its first face.
    pub extra_faces: HashMap<FaceId, Vec<FaceId>>,
    /// Instances that failed to map (so each is reported once).
    pub failed: HashSet<u64>,
    /// Parts made for representations.
    pub rep_parts: HashMap<u64, PartId>,
    /// Parts made for product definitions.
    pub product_parts: HashMap<u64, PartId>,
    /// Failures about instances the file lacks, met with no referrer in hand: reported in
    /// [`Mapper::finish`] at the first instance that references them.
    pub unreferred: Vec<MapError>,
    /// Warnings raised where the mapper is only borrowed (points, directions, placements),
    /// by instance id: moved into the model's warnings in [`Mapper::finish`], one per instance
    /// however often it is read.
    pub notes: std::cell::RefCell<std::collections::BTreeMap<u64, String>>,
}

impl<'f> Mapper<'f> {
    /// A mapper over `file` with an empty model.
    pub fn new(file: &'f StepFile) -> Self {
        Self {
            file,
            model: Model::default(),
            units: Units::default(),
            units_key: 0,
            contexts: HashMap::new(),
            depth: 0,
            surfaces: HashMap::new(),
            curves: HashMap::new(),
            pcurves: HashMap::new(),
            vertices: HashMap::new(),
            edges: HashMap::new(),
            faces: HashMap::new(),
            shells: HashMap::new(),
            solids: HashMap::new(),
            meshes: HashMap::new(),
            coordinates: std::cell::RefCell::new(HashMap::new()),
            extra_faces: HashMap::new(),
            failed: HashSet::new(),
            rep_parts: HashMap::new(),
            product_parts: HashMap::new(),
            unreferred: Vec::new(),
            notes: std::cell::RefCell::new(std::collections::BTreeMap::new()),
        }
    }

    /// The decoded instance `id`, or an error naming it (dangling reference, bad syntax).
    pub fn inst(&self, id: u64) -> MapResult<Instance<'f>> {
        self.file.instance(id).map_err(|d| {
            if self.file.line(id).is_none() {
                MapError::new(id, "reference to an instance that does not exist")
            } else {
                MapError::from(d)
            }
        })
    }

    /// The cache key of `id` under the units in force.
    pub fn key(&self, id: u64) -> Key {
        (id, self.units_key)
    }

    /// Runs `f` one nesting level deeper, failing on `id` past [`MAX_NESTING`].
    pub fn nested<T>(
        &mut self,
        id: u64,
        f: impl FnOnce(&mut Self) -> MapResult<T>,
    ) -> MapResult<T> {
        if self.depth >= MAX_NESTING {
            return Err(MapError::new(
                id,
                format!("references nest deeper than {MAX_NESTING} levels (cyclic?)"),
            ));
        }
        self.depth += 1;
        let r = f(self).map_err(|mut e| {
            if e.context.is_none() && e.id != id {
                e.context = Some(id);
            }
            e
        });
        self.depth -= 1;
        r
    }

    /// Records a mapping failure as a warning (once per instance).
    pub fn report(&mut self, e: &MapError) {
        if self.failed.insert(e.id) {
            match (self.file.line(e.id), e.context) {
                // A missing instance has no line: report it where it is referenced.
                (None, Some(ctx)) => {
                    let line = self.file.line(ctx);
                    self.model
                        .warn(Some(ctx), line, format!("#{}: {}", e.id, e.message));
                }
                (None, None) => self.unreferred.push(e.clone()),
                (line, _) => self.model.warn(Some(e.id), line, e.message.clone()),
            }
        }
    }

    /// Reports each failure of [`Mapper::unreferred`] at the first instance (in file order)
    /// whose text references the missing id, so that every warning names a line: one pass
    /// over the file for all of them.
    fn report_unreferred(&mut self) {
        if self.unreferred.is_empty() {
            return;
        }
        let missing: HashSet<u64> = self.unreferred.iter().map(|e| e.id).collect();
        let mut referrer: HashMap<u64, (u32, u64)> = HashMap::new();
        for id in self.file.ids() {
            let (Some(src), Some(line)) = (self.file.source(id), self.file.line(id)) else {
                continue;
            };
            for r in references(src) {
                if missing.contains(&r) {
                    let e = referrer.entry(r).or_insert((line, id));
                    if line < e.0 {
                        *e = (line, id);
                    }
                }
            }
        }
        for e in std::mem::take(&mut self.unreferred) {
            match referrer.get(&e.id) {
                Some(&(line, by)) => {
                    self.model
                        .warn(Some(by), Some(line), format!("#{}: {}", e.id, e.message))
                }
                None => self.model.warn(
                    Some(e.id),
                    None,
                    format!("{} (and no instance references it)", e.message),
                ),
            }
        }
    }

    /// Records a warning about `id` that is not an error.
    pub fn warn(&mut self, id: u64, message: impl Into<String>) {
        let line = self.file.line(id);
        self.model.warn(Some(id), line, message);
    }

    /// Records a warning about `id` from code that only borrows the mapper; the first note
    /// about an instance is kept (geometry read many times warns once).
    pub fn note(&self, id: u64, message: impl Into<String>) {
        self.notes
            .borrow_mut()
            .entry(id)
            .or_insert_with(|| message.into());
    }

    /// Whether instance `id` has a record with this keyword.
    pub fn is(&self, id: u64, keyword: &str) -> bool {
        self.file.has_keyword(id, keyword)
    }

    /// The finished model.
    pub fn finish(mut self) -> Model {
        self.report_unreferred();
        for (id, message) in std::mem::take(self.notes.get_mut()) {
            self.warn(id, message);
        }
        // Bounds looked at while mapping cached the edge ranges of a partial model.
        self.model.forget_edge_ranges();
        self.model
    }
}

/// The `#id` references in an instance's text (ids inside strings included: a rare false
/// referrer only moves where a warning points).
pub(crate) fn references(src: &[u8]) -> impl Iterator<Item = u64> + '_ {
    src.split(|&b| b == b'#').skip(1).filter_map(|rest| {
        let digits = rest.iter().take_while(|b| b.is_ascii_digit()).count();
        std::str::from_utf8(&rest[..digits]).ok()?.parse().ok()
    })
}
