//! Product structure and assemblies: product definitions, their shape representations, the
//! representations related to those, mapped items, and next-assembly-usage occurrences with
//! their placements. Geometry is mapped once per representation and shared by every
//! occurrence.

use std::collections::{HashMap, HashSet};

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use cadre_brep::assembly::MAX_ASSEMBLY_DEPTH;
use cadre_brep::topology::Wire;
use cadre_brep::{Body, Occurrence, Part, PartId};
use cadre_geom::Transform;

/// Keywords of representations that carry shape (geometry or placements of sub-shapes).
const SHAPE_REPRESENTATIONS: &[&str] = &[
    "SHAPE_REPRESENTATION",
    "ADVANCED_BREP_SHAPE_REPRESENTATION",
    "MANIFOLD_SURFACE_SHAPE_REPRESENTATION",
    "FACETED_BREP_SHAPE_REPRESENTATION",
    "GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION",
    "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION",
    "EDGE_BASED_WIREFRAME_SHAPE_REPRESENTATION",
    "SHELL_BASED_WIREFRAME_SHAPE_REPRESENTATION",
    "TESSELLATED_SHAPE_REPRESENTATION",
    "SHAPE_REPRESENTATION_WITH_PARAMETERS",
    "MANIFOLD_SUBSURFACE_SHAPE_REPRESENTATION",
    "NON_MANIFOLD_SURFACE_SHAPE_REPRESENTATION",
    "CONSTRUCTIVE_GEOMETRY_REPRESENTATION",
];

/// More part instances than this in one model means a corrupt or hostile file (a chain of
/// assemblies each using the next many times); such trees are cut.
pub const MAX_INSTANCES: u64 = 50_000_000;

/// Relationships read from the file before any geometry is mapped.
#[derive(Default)]
struct ProductGraph {
    /// Product definition → its shape representations (through SDR and PDS).
    pd_reps: HashMap<u64, Vec<u64>>,
    /// Representation → representations related to it without a transform (both directions:
    /// a product's shape is everything so related to its representations, as CAD kernels
    /// read it).
    rep_links: HashMap<u64, Vec<u64>>,
    /// Representations included by another one (not roots).
    included_reps: HashSet<u64>,
    /// NAUO id → (parent PD, child PD, name).
    usages: Vec<(u64, u64, u64, String)>,
    /// NAUO id → representation relationship holding its placement.
    usage_placement: HashMap<u64, u64>,
}

fn is_shape_rep(m: &Mapper<'_>, id: u64) -> bool {
    SHAPE_REPRESENTATIONS.iter().any(|k| m.is(id, k))
}

fn read_graph(m: &mut Mapper<'_>) -> ProductGraph {
    let mut g = ProductGraph::default();
    // Product definition shapes: which PD or NAUO each one characterises.
    let mut pds_def: HashMap<u64, u64> = HashMap::new();
    for id in m.file.ids_with_keyword("PRODUCT_DEFINITION_SHAPE") {
        match m.inst(id).and_then(|i| Attrs::first(&i)?.r#ref(2)) {
            Ok(def) => {
                pds_def.insert(id, def);
            }
            Err(e) => m.report(&e),
        }
    }
    for id in m.file.ids_with_keyword("SHAPE_DEFINITION_REPRESENTATION") {
        let r = m.inst(id).and_then(|i| {
            let a = Attrs::first(&i)?;
            Ok((a.r#ref(0)?, a.r#ref(1)?))
        });
        match r {
            Ok((pds, rep)) => {
                if let Some(&def) = pds_def.get(&pds) {
                    g.pd_reps.entry(def).or_default().push(rep);
                }
            }
            Err(e) => m.report(&e),
        }
    }
    for id in m.file.ids_with_keyword("NEXT_ASSEMBLY_USAGE_OCCURRENCE") {
        let r = m.inst(id).and_then(|i| {
            let a =
                Attrs::of(&i, "NEXT_ASSEMBLY_USAGE_OCCURRENCE").or_else(|_| Attrs::first(&i))?;
            let name = match a.str_or_empty(1) {
                n if n.is_empty() => a.str_or_empty(0),
                n => n,
            };
            Ok((a.r#ref(3)?, a.r#ref(4)?, name))
        });
        match r {
            Ok((parent, child, name)) => {
                let parent = usage_end(m, &pds_def, id, parent, "relating");
                let child = usage_end(m, &pds_def, id, child, "related");
                g.usages.push((id, parent, child, name))
            }
            Err(e) => m.report(&e),
        }
    }
    let mut placed_relations = HashSet::new();
    for id in m
        .file
        .ids_with_keyword("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION")
    {
        let r = m.inst(id).and_then(|i| {
            let a = Attrs::first(&i)?;
            Ok((a.r#ref(0)?, a.r#ref(1)?))
        });
        match r {
            Ok((relation, pds)) => {
                placed_relations.insert(relation);
                if let Some(&nauo) = pds_def.get(&pds) {
                    g.usage_placement.insert(nauo, relation);
                }
            }
            Err(e) => m.report(&e),
        }
    }
    let product_reps: HashSet<u64> = g.pd_reps.values().flatten().copied().collect();
    let mut relations = m.file.ids_with_keyword("REPRESENTATION_RELATIONSHIP");
    relations.extend(m.file.ids_with_keyword("SHAPE_REPRESENTATION_RELATIONSHIP"));
    // Supplemental geometry (AP242) hangs off a part's shape through this relationship.
    relations.extend(
        m.file
            .ids_with_keyword("CONSTRUCTIVE_GEOMETRY_REPRESENTATION_RELATIONSHIP"),
    );
    relations.sort_unstable();
    relations.dedup();
    for id in relations {
        if placed_relations.contains(&id) {
            continue;
        }
        let Ok(inst) = m.inst(id) else { continue };
        let Some(rec) = inst
            .record("REPRESENTATION_RELATIONSHIP")
            .or(inst.records.first())
        else {
            continue;
        };
        let (Some(r1), Some(r2)) = (
            rec.params.get(2).and_then(|p| p.as_ref_id()),
            rec.params.get(3).and_then(|p| p.as_ref_id()),
        ) else {
            continue;
        };
        if !(is_shape_rep(m, r1) && is_shape_rep(m, r2)) {
            continue;
        }
        // Usually (rep_1 = shape representation, rep_2 = its geometry); the one not owned by
        // a product is the included one when roots are sought without products.
        let child = if product_reps.contains(&r2) && !product_reps.contains(&r1) {
            r1
        } else {
            r2
        };
        g.rep_links.entry(r1).or_default().push(r2);
        g.rep_links.entry(r2).or_default().push(r1);
        g.included_reps.insert(child);
    }
    g
}

/// The product definition an assembly usage names as its `role` end. Some writers name the
/// product definition's `PRODUCT_DEFINITION_SHAPE` instead (bug25167.stp: 4 of 9 usages);
/// CAD kernels follow it to the definition it characterises, and so does this, with a warning.
fn usage_end(
    m: &mut Mapper<'_>,
    pds_def: &HashMap<u64, u64>,
    nauo: u64,
    end: u64,
    role: &str,
) -> u64 {
    if m.is(end, "PRODUCT_DEFINITION_SHAPE")
        && let Some(&def) = pds_def.get(&end)
        && !m.is(def, "NEXT_ASSEMBLY_USAGE_OCCURRENCE")
    {
        m.warn(
            nauo,
            format!(
                "assembly usage names the product definition shape #{end} as its {role} \
                 product definition; read as the definition it characterises, #{def}"
            ),
        );
        return def;
    }
    end
}

/// Every representation reachable from `start` through relationships without transforms.
fn rep_closure(g: &ProductGraph, start: &[u64]) -> Vec<u64> {
    let mut seen: HashSet<u64> = HashSet::new();
    let mut order = Vec::new();
    let mut stack: Vec<u64> = start.iter().rev().copied().collect();
    while let Some(r) = stack.pop() {
        if !seen.insert(r) {
            continue;
        }
        order.push(r);
        for &n in g
            .rep_links
            .get(&r)
            .map(Vec::as_slice)
            .unwrap_or(&[])
            .iter()
            .rev()
        {
            if !seen.contains(&n) {
                stack.push(n);
            }
        }
    }
    order
}

/// Places the parts of `reps` (and of everything related to them) in `part`, untransformed.
fn attach_reps(m: &mut Mapper<'_>, g: &ProductGraph, part: PartId, reps: &[u64]) {
    for rep in rep_closure(g, reps) {
        match rep_part(m, g, rep) {
            Ok(child) => m.model.parts[part.index()].children.push(Occurrence {
                part: child,
                transform: Transform::IDENTITY,
                name: String::new(),
                step_id: rep,
            }),
            Err(e) => m.report(&e),
        }
    }
}

/// The name of a product definition's product (its part name), else its id.
fn product_names(m: &Mapper<'_>, pd: u64) -> MapResult<(String, String)> {
    let inst = m.inst(pd)?;
    let a = Attrs::first(&inst)?;
    let formation = a.r#ref(2)?;
    let f = m.inst(formation)?;
    let fa = Attrs::first(&f)?;
    let product = fa.r#ref(2)?;
    let p = m.inst(product)?;
    let pa = Attrs::first(&p)?;
    let id = pa.str_or_empty(0);
    let name = pa.str_or_empty(1);
    Ok((if name.is_empty() { id.clone() } else { name }, id))
}

/// Maps the product structure and everything it references into parts and roots.
pub fn map_products(m: &mut Mapper<'_>) {
    let g = read_graph(m);
    let mut pds = m.file.ids_with_keyword("PRODUCT_DEFINITION");
    pds.extend(
        m.file
            .ids_with_keyword("PRODUCT_DEFINITION_WITH_ASSOCIATED_DOCUMENTS"),
    );
    pds.sort_unstable();
    pds.dedup();

    for &pd in &pds {
        let (name, product_id) = product_names(m, pd).unwrap_or_else(|e| {
            m.report(&e);
            (String::new(), String::new())
        });
        let pid = PartId(m.model.parts.len() as u32);
        m.model.parts.push(Part {
            name,
            product_id,
            is_product: true,
            step_id: pd,
            ..Part::default()
        });
        m.product_parts.insert(pd, pid);
    }
    for &pd in &pds {
        let pid = m.product_parts[&pd];
        let reps = g.pd_reps.get(&pd).cloned().unwrap_or_default();
        attach_reps(m, &g, pid, &reps);
    }
    let mut children_pds = HashSet::new();
    for (nauo, parent, child, name) in &g.usages {
        let (Some(&pp), Some(&cp)) = (m.product_parts.get(parent), m.product_parts.get(child))
        else {
            m.warn(
                *nauo,
                "assembly usage refers to an unknown product definition; skipped",
            );
            continue;
        };
        children_pds.insert(*child);
        let transform = match g.usage_placement.get(nauo) {
            Some(&relation) => match usage_transform(m, &g, relation, *child) {
                Ok(t) => t,
                Err(e) => {
                    m.report(&e);
                    Transform::IDENTITY
                }
            },
            None => {
                if placed_by_mapped_item(m, &g, pp, *child) {
                    // The parent's shape already places the child's shape with a mapped
                    // item: that is this usage; adding it again would count it twice.
                    continue;
                }
                Transform::IDENTITY
            }
        };
        m.model.parts[pp.index()].children.push(Occurrence {
            part: cp,
            transform,
            name: name.clone(),
            step_id: *nauo,
        });
    }
    let mut roots: Vec<PartId> = pds
        .iter()
        .filter(|pd| !children_pds.contains(pd))
        .map(|pd| m.product_parts[pd])
        .collect();
    if roots.is_empty() || !has_geometry_below(m, &roots) {
        // No product structure (or none with shape): every shape representation not
        // included by another is a root.
        let mut reps = Vec::new();
        for k in SHAPE_REPRESENTATIONS {
            reps.extend(m.file.ids_with_keyword(k));
        }
        reps.sort_unstable();
        reps.dedup();
        let used: HashSet<u64> = g.pd_reps.values().flatten().copied().collect();
        for rep in reps {
            if g.included_reps.contains(&rep)
                || used.contains(&rep)
                || m.rep_parts.contains_key(&rep)
            {
                continue;
            }
            // A root of its own: a part holding the representation and those related to it.
            let pid = PartId(m.model.parts.len() as u32);
            m.model.parts.push(Part {
                step_id: rep,
                ..Part::default()
            });
            attach_reps(m, &g, pid, &[rep]);
            let first = m.model.parts[pid.index()].children.first().map(|o| o.part);
            if let Some(first) = first {
                m.model.parts[pid.index()].name = m.model.parts[first.index()].name.clone();
            }
            roots.push(pid);
        }
    }
    if !has_geometry_below(m, &roots)
        && let Some(part) = loose_geometry(m, &g)
    {
        roots.push(part);
    }
    m.model.roots = roots;
    break_cycles(m);
    limit_instances(m);
    limit_depth(m);
}

/// Whether product part `parent` places one of `child_pd`'s representations through a
/// `MAPPED_ITEM` in one of its own representations.
fn placed_by_mapped_item(m: &Mapper<'_>, g: &ProductGraph, parent: PartId, child_pd: u64) -> bool {
    let child_parts: HashSet<PartId> = g
        .pd_reps
        .get(&child_pd)
        .into_iter()
        .flatten()
        .filter_map(|r| m.rep_parts.get(r).copied())
        .collect();
    m.model.parts[parent.index()].children.iter().any(|rep| {
        m.model.parts[rep.part.index()]
            .children
            .iter()
            .any(|o| child_parts.contains(&o.part) && m.is(o.step_id, "MAPPED_ITEM"))
    })
}

fn has_geometry_below(m: &Mapper<'_>, roots: &[PartId]) -> bool {
    let mut stack: Vec<PartId> = roots.to_vec();
    let mut seen = HashSet::new();
    while let Some(p) = stack.pop() {
        if !seen.insert(p) {
            continue;
        }
        let part = &m.model.parts[p.index()];
        if !part.bodies.is_empty() {
            return true;
        }
        stack.extend(part.children.iter().map(|o| o.part));
    }
    false
}

/// Geometry that no representation brought in (a truncated file whose representations and
/// product structure were in the lost tail, or geometry written without any representation),
/// gathered into one part so valid geometry is never lost: solid-level items, then shells that
/// no solid in the file uses, then faces that no shell in the file uses.
fn loose_geometry(m: &mut Mapper<'_>, g: &ProductGraph) -> Option<PartId> {
    const TOP_LEVEL: &[&str] = &[
        "MANIFOLD_SOLID_BREP",
        "BREP_WITH_VOIDS",
        "FACETED_BREP",
        "SHELL_BASED_SURFACE_MODEL",
        "TESSELLATED_SOLID",
        "TESSELLATED_SHELL",
    ];
    const SHELLS: &[&str] = &[
        "CLOSED_SHELL",
        "OPEN_SHELL",
        "ORIENTED_CLOSED_SHELL",
        "ORIENTED_OPEN_SHELL",
    ];
    const FACES: &[&str] = &["ADVANCED_FACE", "FACE_SURFACE"];
    let with_keywords = |keywords: &[&str]| -> Vec<u64> {
        let mut ids: Vec<u64> = keywords
            .iter()
            .flat_map(|k| m.file.ids_with_keyword(k))
            .collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    };
    // What the instances of one level reference: a shell is loose when no solid-level item
    // and no other shell (an oriented shell, a void) names it, a face when no shell does.
    let referenced_by = |ids: &[u64]| -> HashSet<u64> {
        ids.iter()
            .filter_map(|&id| Some((id, m.file.source(id)?)))
            .flat_map(|(id, src)| super::context::references(src).filter(move |&r| r != id))
            .collect()
    };
    let top = with_keywords(TOP_LEVEL);
    let shells = with_keywords(SHELLS);
    let in_solids = referenced_by(&top);
    let in_shells = referenced_by(&shells);
    let loose_shells: Vec<u64> = shells
        .iter()
        .copied()
        .filter(|s| !in_solids.contains(s) && !in_shells.contains(s))
        .collect();
    let loose_faces: Vec<u64> = with_keywords(FACES)
        .into_iter()
        .filter(|f| !in_shells.contains(f))
        .collect();
    let mut ids = top;
    ids.extend(&loose_shells);
    ids.extend(&loose_faces);
    if ids.is_empty() {
        return None;
    }
    // The first context in the file gives the units (geometry has no other link to one).
    let ctx = m
        .file
        .ids_with_keyword("GLOBAL_UNIT_ASSIGNED_CONTEXT")
        .first()
        .copied();
    let saved = m.enter_context(ctx);
    let mut bodies = Vec::new();
    let mut children = Vec::new();
    for &id in &ids {
        if let Err(e) = map_item(m, g, id, &mut bodies, &mut children) {
            m.report(&e);
        }
    }
    m.restore_units(saved);
    if bodies.is_empty() {
        return None;
    }
    m.warn(
        ids[0],
        format!(
            "{} bodies ({} solid-level items, {} shells in no solid, {} faces in no shell) are not in any shape representation; loaded as one part",
            bodies.len(),
            ids.len() - loose_shells.len() - loose_faces.len(),
            loose_shells.len(),
            loose_faces.len(),
        ),
    );
    let pid = PartId(m.model.parts.len() as u32);
    m.model.parts.push(Part {
        name: "(unreferenced geometry)".into(),
        bodies,
        children,
        step_id: ids[0],
        ..Part::default()
    });
    Some(pid)
}

/// The child → parent transform of an assembly usage from its representation relationship.
fn usage_transform(
    m: &mut Mapper<'_>,
    g: &ProductGraph,
    relation: u64,
    child_pd: u64,
) -> MapResult<Transform> {
    let inst = m.inst(relation)?;
    let rr = inst
        .record("REPRESENTATION_RELATIONSHIP")
        .ok_or_else(|| MapError::new(relation, "expected a REPRESENTATION_RELATIONSHIP"))?;
    let rr = Attrs {
        id: relation,
        keyword: rr.keyword,
        params: &rr.params,
    };
    let (rep1, rep2) = (rr.r#ref(2)?, rr.r#ref(3)?);
    let op = inst
        .record("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")
        .and_then(|r| r.params.first())
        .and_then(|p| p.as_ref_id())
        .ok_or_else(|| MapError::new(relation, "relationship has no transformation"))?;
    let child_reps = g.pd_reps.get(&child_pd).map(Vec::as_slice).unwrap_or(&[]);
    // The operator takes rep_1 into rep_2; exporters write either order of parent and child.
    let rep1_is_child = child_reps.contains(&rep1) || !child_reps.contains(&rep2);
    let t = if m.is(op, "ITEM_DEFINED_TRANSFORMATION") {
        let i = m.inst(op)?;
        let a = Attrs::first(&i)?;
        let (item1, item2) = (a.r#ref(2)?, a.r#ref(3)?);
        let a1 = placement_in(m, rep1, item1)?;
        let a2 = placement_in(m, rep2, item2)?;
        // The item that the child's representation lists is the child's origin, whatever
        // order the relationship names the representations in (writers differ).
        let child_items: HashSet<u64> = child_reps.iter().flat_map(|&r| rep_items(m, r)).collect();
        if child_items.contains(&item1) && !child_items.contains(&item2) {
            return finite(relation, a2 * a1.inverse());
        }
        if child_items.contains(&item2) && !child_items.contains(&item1) {
            return finite(relation, a1 * a2.inverse());
        }
        a2 * a1.inverse()
    } else {
        let saved = m.enter_context(rep_context(m, rep2));
        let t = m.transform(op);
        m.restore_units(saved);
        t?
    };
    finite(relation, if rep1_is_child { t } else { t.inverse() })
}

fn finite(relation: u64, t: Transform) -> MapResult<Transform> {
    if t.is_finite() {
        Ok(t)
    } else {
        Err(MapError::new(relation, "placement is not invertible"))
    }
}

/// The items a representation lists.
fn rep_items(m: &Mapper<'_>, rep: u64) -> Vec<u64> {
    m.inst(rep)
        .ok()
        .and_then(|i| {
            let rec = i.record("REPRESENTATION").or(i.records.first())?;
            Some(
                rec.params
                    .get(1)?
                    .as_list()?
                    .iter()
                    .filter_map(|p| p.as_ref_id())
                    .collect(),
            )
        })
        .unwrap_or_default()
}

/// A placement item mapped in the units of the representation it belongs to.
fn placement_in(m: &mut Mapper<'_>, rep: u64, item: u64) -> MapResult<Transform> {
    let saved = m.enter_context(rep_context(m, rep));
    let t = m.transform(item);
    m.restore_units(saved);
    t
}

/// The coordinate space dimension of a geometric representation context.
fn context_dimension(m: &Mapper<'_>, ctx: u64) -> Option<i64> {
    let inst = m.inst(ctx).ok()?;
    let rec = inst.record("GEOMETRIC_REPRESENTATION_CONTEXT")?;
    rec.params.iter().rev().find_map(|p| p.as_i64())
}

fn rep_context(m: &Mapper<'_>, rep: u64) -> Option<u64> {
    let inst = m.inst(rep).ok()?;
    let rec = inst
        .record("REPRESENTATION")
        .or(inst.records.iter().find(|r| r.params.len() >= 3))?;
    rec.params.get(2).and_then(|p| p.as_ref_id())
}

/// The part for a shape representation: its geometric items as bodies, its mapped items and
/// included representations as children. Built once per representation.
fn rep_part(m: &mut Mapper<'_>, g: &ProductGraph, rep: u64) -> MapResult<PartId> {
    if let Some(&p) = m.rep_parts.get(&rep) {
        return Ok(p);
    }
    let inst = m.inst(rep)?;
    let rec = inst
        .record("REPRESENTATION")
        .or(inst.records.first())
        .ok_or_else(|| MapError::new(rep, "empty representation"))?;
    let a = Attrs {
        id: rep,
        keyword: rec.keyword,
        params: &rec.params,
    };
    let name = a.str_or_empty(0);
    let items = a.refs(1)?;
    let ctx = a.opt_ref(2);
    let pid = PartId(m.model.parts.len() as u32);
    // Registered before its content so a representation that includes itself is caught.
    m.model.parts.push(Part {
        name,
        step_id: rep,
        ..Part::default()
    });
    m.rep_parts.insert(rep, pid);
    if ctx.is_some_and(|c| context_dimension(m, c) == Some(2)) {
        // A drawing's 2D geometry (views, sketches): not part of the 3D model.
        return Ok(pid);
    }
    let saved = m.enter_context(ctx);
    let mut bodies = Vec::new();
    let mut children = Vec::new();
    for item in items {
        if let Err(e) = map_item(m, g, item, &mut bodies, &mut children) {
            m.report(&e);
        }
    }
    m.restore_units(saved);
    let part = &mut m.model.parts[pid.index()];
    part.bodies = bodies;
    part.children = children;
    Ok(pid)
}

/// Maps one representation item into bodies or child occurrences.
fn map_item(
    m: &mut Mapper<'_>,
    g: &ProductGraph,
    item: u64,
    bodies: &mut Vec<Body>,
    children: &mut Vec<Occurrence>,
) -> MapResult<()> {
    let inst = m.inst(item)?;
    let keyword = inst.keyword();
    let has = |k: &str| inst.has(k);
    if has("MANIFOLD_SOLID_BREP") || has("BREP_WITH_VOIDS") || has("FACETED_BREP") {
        let solid = m.solid(item)?;
        bodies.extend(solid_or_shells(m, item, solid));
    } else if matches!(
        keyword,
        "SHELL_BASED_SURFACE_MODEL" | "FACE_BASED_SURFACE_MODEL"
    ) {
        for shell in Attrs::first(&inst)?.refs(1)? {
            match m.shell(shell) {
                Ok((s, _)) => bodies.push(Body::Shell(s)),
                Err(e) => m.report(&e),
            }
        }
    } else if matches!(
        keyword,
        "CLOSED_SHELL" | "OPEN_SHELL" | "ORIENTED_CLOSED_SHELL" | "ORIENTED_OPEN_SHELL"
    ) {
        bodies.push(Body::Shell(m.shell(item)?.0));
    } else if matches!(keyword, "ADVANCED_FACE" | "FACE_SURFACE") {
        bodies.push(Body::Face(m.face(item)?));
    } else if matches!(
        keyword,
        "TESSELLATED_SOLID"
            | "TESSELLATED_SHELL"
            | "TRIANGULATED_FACE"
            | "COMPLEX_TRIANGULATED_FACE"
            | "TRIANGULATED_SURFACE_SET"
            | "COMPLEX_TRIANGULATED_SURFACE_SET"
    ) {
        bodies.push(Body::Mesh(m.tessellated(item)?));
    } else if matches!(keyword, "GEOMETRIC_SET" | "GEOMETRIC_CURVE_SET") {
        for element in Attrs::first(&inst)?.refs(1)? {
            if m.is(element, "CARTESIAN_POINT") {
                bodies.push(Body::Point(m.point3(element)?));
            } else if super::topology::SURFACE_KEYWORDS
                .iter()
                .any(|k| m.is(element, k))
            {
                match m.surface_face(element) {
                    Ok(f) => {
                        bodies.push(Body::Face(f));
                        let extra = m.extra_faces.get(&f).cloned().unwrap_or_default();
                        bodies.extend(extra.into_iter().map(Body::Face));
                    }
                    Err(e) => m.report(&e),
                }
            } else if is_curve(m, element) {
                match m.curve_id(element) {
                    Ok(curve) => bodies.push(Body::Wire(Wire { curve, range: None })),
                    Err(e) => m.report(&e),
                }
            }
        }
    } else if keyword == "EDGE_BASED_WIREFRAME_MODEL" {
        for set in Attrs::first(&inst)?.refs(1)? {
            let s = m.inst(set)?;
            for edge in Attrs::first(&s)?.refs(1)? {
                match m.edge(edge) {
                    Ok(e) => bodies.push(Body::Edge(e)),
                    Err(e) => m.report(&e),
                }
            }
        }
    } else if keyword == "MAPPED_ITEM" {
        children.push(mapped_item(m, g, item)?);
    }
    // Placements, styled or descriptive items: nothing to draw.
    Ok(())
}

/// A solid whose outer shell is open bounds no volume: it is read as its shell's connected
/// pieces, with a warning, as CAD kernels heal it.
fn solid_or_shells(m: &mut Mapper<'_>, item: u64, solid: cadre_brep::SolidId) -> Vec<Body> {
    let outer = m.model.solids[solid.index()].outer;
    let free = m.model.free_edges(outer, cadre_geom::Accuracy::default());
    if free == 0 {
        return vec![Body::Solid(solid)];
    }
    let pieces = m.model.shell_components(outer);
    let step_id = m.model.shells[outer.index()].step_id;
    let mut bodies = Vec::new();
    for faces in pieces {
        let sid = cadre_brep::ShellId(m.model.shells.len() as u32);
        m.model.shells.push(cadre_brep::Shell {
            faces,
            closed: false,
            step_id,
        });
        bodies.push(Body::Shell(sid));
    }
    m.warn(
        item,
        format!(
            "solid's shell is open ({free} free edges): read as {} open shell(s)",
            bodies.len()
        ),
    );
    bodies
}

fn is_curve(m: &Mapper<'_>, id: u64) -> bool {
    [
        "LINE",
        "CIRCLE",
        "ELLIPSE",
        "PARABOLA",
        "HYPERBOLA",
        "POLYLINE",
        "TRIMMED_CURVE",
        "COMPOSITE_CURVE",
        "B_SPLINE_CURVE",
        "B_SPLINE_CURVE_WITH_KNOTS",
        "BEZIER_CURVE",
        "OFFSET_CURVE_3D",
        "SURFACE_CURVE",
        "SEAM_CURVE",
        "INTERSECTION_CURVE",
        "QUASI_UNIFORM_CURVE",
        "UNIFORM_CURVE",
    ]
    .iter()
    .any(|k| m.is(id, k))
}

/// A `MAPPED_ITEM`: another representation placed in this one.
fn mapped_item(m: &mut Mapper<'_>, g: &ProductGraph, id: u64) -> MapResult<Occurrence> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "MAPPED_ITEM")?;
    let name = a.str_or_empty(0);
    let source = a.r#ref(1)?;
    let target = a.r#ref(2)?;
    let s = m.inst(source)?;
    let sa = Attrs::of(&s, "REPRESENTATION_MAP")?;
    let origin_item = sa.r#ref(0)?;
    let rep = sa.r#ref(1)?;
    let target_t = m.transform(target)?;
    let origin_t = placement_in(m, rep, origin_item)?;
    let part = m.nested(id, |m| rep_part(m, g, rep))?;
    let transform = target_t * origin_t.inverse();
    if !transform.is_finite() {
        return Err(a.err("mapping origin is not invertible"));
    }
    Ok(Occurrence {
        part,
        transform,
        name,
        step_id: id,
    })
}

/// Removes child links that close a cycle (a part that contains itself), with a warning.
fn break_cycles(m: &mut Mapper<'_>) {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        New,
        Open,
        Done,
    }
    let n = m.model.parts.len();
    let mut state = vec![State::New; n];
    let mut dropped = Vec::new();
    for start in 0..n {
        if state[start] != State::New {
            continue;
        }
        // Iterative depth-first search: (part, next child index).
        let mut stack = vec![(start, 0usize)];
        state[start] = State::Open;
        while let Some(&mut (p, ref mut next)) = stack.last_mut() {
            if let Some(occ) = m.model.parts[p].children.get(*next) {
                *next += 1;
                let c = occ.part.index();
                match state[c] {
                    State::New => {
                        state[c] = State::Open;
                        stack.push((c, 0));
                    }
                    State::Open => dropped.push((p, occ.step_id, c)),
                    State::Done => {}
                }
            } else {
                state[p] = State::Done;
                stack.pop();
            }
        }
    }
    for (p, step_id, c) in dropped {
        m.model.parts[p]
            .children
            .retain(|o| !(o.step_id == step_id && o.part.index() == c));
        m.warn(
            step_id,
            "assembly cycle: a part would contain itself; this usage is dropped",
        );
    }
}

/// Counts instances per part bottom-up; if the tree would expand past [`MAX_INSTANCES`],
/// cuts the offending children with a warning so walking the tree stays bounded.
fn limit_instances(m: &mut Mapper<'_>) {
    let n = m.model.parts.len();
    let order = post_order(m);
    let mut count: Vec<Option<u64>> = vec![None; n];
    for &p in &order {
        let mut total: u64 = 1;
        for o in &m.model.parts[p].children {
            total = total.saturating_add(count[o.part.index()].unwrap_or(1));
        }
        if total > MAX_INSTANCES {
            let step_id = m.model.parts[p].step_id;
            m.model.parts[p].children.clear();
            m.warn(
                step_id,
                format!("assembly expands to more than {MAX_INSTANCES} instances; its children are dropped"),
            );
            total = 1;
        }
        count[p] = Some(total);
    }
}

/// Part indices with every part after all the parts it places (the graph is acyclic after
/// `break_cycles`), iteratively.
fn post_order(m: &Mapper<'_>) -> Vec<usize> {
    let n = m.model.parts.len();
    let mut order = Vec::with_capacity(n);
    let mut visited = vec![false; n];
    for start in 0..n {
        if visited[start] {
            continue;
        }
        let mut stack = vec![(start, false)];
        while let Some((p, expanded)) = stack.pop() {
            if expanded {
                order.push(p);
                continue;
            }
            if visited[p] {
                continue;
            }
            visited[p] = true;
            stack.push((p, true));
            for o in &m.model.parts[p].children {
                if !visited[o.part.index()] {
                    stack.push((o.part.index(), false));
                }
            }
        }
    }
    order
}

/// Cuts assemblies nesting deeper than [`MAX_ASSEMBLY_DEPTH`] levels at the part where the
/// cap is reached, with a warning: the walks of the tree stop there, and a tree cut without
/// one loaded 300 nested levels as nothing at all, silently.
fn limit_depth(m: &mut Mapper<'_>) {
    let n = m.model.parts.len();
    let mut height: Vec<usize> = vec![0; n];
    for p in post_order(m) {
        let h = m.model.parts[p]
            .children
            .iter()
            .map(|o| height[o.part.index()] + 1)
            .max()
            .unwrap_or(0);
        if h > MAX_ASSEMBLY_DEPTH {
            let step_id = m.model.parts[p].step_id;
            m.model.parts[p].children.clear();
            m.warn(
                step_id,
                format!(
                    "assembly nests deeper than {MAX_ASSEMBLY_DEPTH} levels; the parts below \
                     this one are dropped"
                ),
            );
            height[p] = 0;
        } else {
            height[p] = h;
        }
    }
}
