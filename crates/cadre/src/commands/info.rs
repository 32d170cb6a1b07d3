//! `cadre info`: what a STEP file holds.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Result;
use cadre_brep::{Model, PartId};
use cadre_geom::Accuracy;
use cadre_step::syntax::StepFile;
use serde_json::json;

use crate::load::load_step;

/// Arguments of `cadre info`.
#[derive(clap::Args)]
pub struct InfoArgs {
    /// The STEP file (.stp, .step, .p21).
    file: PathBuf,
    /// Print one JSON object instead of the human summary.
    #[arg(long)]
    json: bool,
    /// Also list every face: STEP id, surface type, (u, v) bounds and box in mm.
    #[arg(long)]
    faces: bool,
    /// With --faces, also each face's edges with their parameter ranges on their curves.
    #[arg(long, requires = "faces")]
    edges: bool,
    /// Show at most this many warnings in the human summary (all are in --json).
    #[arg(long, default_value_t = 20)]
    max_warnings: usize,
}

/// The application protocol a schema name belongs to.
fn protocol(schema: &str) -> &'static str {
    let s = schema.to_ascii_uppercase();
    if s.starts_with("AP242") {
        "AP242"
    } else if s.starts_with("AUTOMOTIVE_DESIGN") {
        "AP214"
    } else if s.starts_with("CONFIG_CONTROL_DESIGN") || s.starts_with("AP203") {
        "AP203"
    } else if s.starts_with("STRUCTURAL_ANALYSIS_DESIGN") || s.starts_with("AP209") {
        "AP209"
    } else {
        "unknown protocol"
    }
}

/// Instances of each entity keyword in the file (each record of a complex instance counts).
fn entity_counts(file: &StepFile) -> BTreeMap<String, u64> {
    let mut counts = BTreeMap::new();
    for id in file.ids() {
        for &k in file.keywords(id).unwrap_or(&[]) {
            *counts.entry(file.keyword_name(k).to_string()).or_default() += 1;
        }
    }
    counts
}

/// Lines of the product tree: each child part once with how many times its parent uses it.
fn tree_lines(model: &Model, part: PartId, depth: usize, uses: usize, out: &mut Vec<String>) {
    const MAX_LINES: usize = 200;
    if out.len() >= MAX_LINES || depth > 32 {
        return;
    }
    let p = model.part(part);
    let name = if p.name.is_empty() {
        "(unnamed)"
    } else {
        &p.name
    };
    let mut what = Vec::new();
    if !p.bodies.is_empty() {
        what.push(format!("{} bodies", p.bodies.len()));
    }
    let times = if uses > 1 {
        format!(" ×{uses}")
    } else {
        String::new()
    };
    let kind = if p.is_product {
        ""
    } else {
        " [representation]"
    };
    out.push(format!(
        "{}{name}{times}{kind}{}",
        "  ".repeat(depth + 1),
        if what.is_empty() {
            String::new()
        } else {
            format!(" ({})", what.join(", "))
        }
    ));
    let mut grouped: Vec<(PartId, usize)> = Vec::new();
    for occ in &p.children {
        match grouped.iter_mut().find(|(id, _)| *id == occ.part) {
            Some((_, n)) => *n += 1,
            None => grouped.push((occ.part, 1)),
        }
    }
    for (child, n) in grouped {
        tree_lines(model, child, depth + 1, n, out);
    }
}

/// One line per face: its STEP id, surface type, (u, v) bounds and box (part coordinates),
/// optionally followed by its edges' parameter ranges and curve domains.
fn print_faces(model: &Model, with_edges: bool) {
    let acc = Accuracy::default();
    println!("faces (part coordinates)");
    for face in &model.faces {
        let surface = &model.surfaces[face.surface.index()];
        let (b, _) = cadre_brep::bounds::face_bounds(model, face, acc);
        let uv = cadre_brep::bounds::face_uv_box(model, face, surface, acc)
            .map(|uv| {
                format!(
                    "u [{:.4}, {:.4}] v [{:.4}, {:.4}]",
                    uv[0], uv[1], uv[2], uv[3]
                )
            })
            .unwrap_or_else(|| "no (u, v) bounds".into());
        let bb = b.to_array().map(|x| format!("{x:.4}")).join(", ");
        println!(
            "  #{:<8} {:<22} {} box [{bb}]",
            face.step_id,
            cadre_brep::bounds::reported_type(surface),
            uv
        );
        if with_edges {
            for lp in &face.loops {
                if let cadre_brep::LoopKind::Edges(es) = &lp.kind {
                    for oe in es {
                        let e = &model.edges[oe.edge.index()];
                        let r = model.edge_range(oe.edge, acc);
                        let d = e.curve.and_then(|c| model.curves[c.index()].domain());
                        println!("      edge #{} range {r:?} domain {d:?}", e.step_id);
                    }
                }
            }
        }
    }
}

/// The model's PMI as `cadre info --json` lists it: annotations, dimensions, tolerances,
/// datums and datum targets counted as OCCT's XCAF document counts them (dimensions include
/// one per tessellated annotation; items no geometric usage ties to the shape are left out),
/// the saved views' names (drawing sheets' views apart), and what the annotations hold.
fn pmi_json(pmi: &cadre_brep::Pmi) -> serde_json::Value {
    let s = &pmi.semantic;
    json!({
        "annotations": pmi.annotations.len(),
        "dimensions": pmi.occt_dimensions(),
        "tolerances": pmi.occt_tolerances(),
        "datums": s.datums(),
        "datum_targets": s.datum_targets(),
        "saved_views": pmi.saved_views().map(|v| v.name.as_str()).collect::<Vec<_>>(),
        "drawing_views": pmi
            .views
            .iter()
            .filter(|v| v.drawing)
            .map(|v| v.name.as_str())
            .collect::<Vec<_>>(),
        "semantic_dimensions": s.dimensions(),
        "annotation_planes": pmi.planes.len(),
        "annotation_points": pmi.annotations.iter().map(|a| a.point_count()).sum::<usize>(),
        "annotation_texts": pmi.annotations.iter().map(|a| a.texts.len()).sum::<usize>(),
        "semantic": semantic_json(pmi),
    })
}

/// Each semantic PMI item: its STEP id, type, text as a feature-control frame writes it, how
/// many faces it applies to, whether an annotation presents it, and whether OCCT's XCAF
/// document would count it.
fn semantic_json(pmi: &cadre_brep::Pmi) -> Vec<serde_json::Value> {
    use cadre_brep::pmi::SemanticItem;
    let presented: std::collections::HashSet<usize> =
        pmi.annotations.iter().filter_map(|a| a.semantic).collect();
    pmi.semantic
        .items
        .iter()
        .enumerate()
        .map(|(k, item)| {
            let kind = match item {
                SemanticItem::Dimension { .. } => "dimension",
                SemanticItem::Tolerance { .. } => "tolerance",
                SemanticItem::Datum { .. } => "datum",
                SemanticItem::DatumTarget { .. } => "datum_target",
            };
            json!({
                "step_id": item.step_id(),
                "type": kind,
                "text": cadre_render::pmi::semantic_text(item),
                "faces": item.faces().len(),
                "presented": presented.contains(&k),
                "occt_label": !pmi.semantic.xcaf_unlabelled.contains(&item.step_id()),
            })
        })
        .collect()
}

/// Runs `cadre info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let loaded = load_step(&args.file)?;
    let model = &loaded.model;
    let counts = model.counts();
    let bbox = model.bbox(Accuracy::default());
    let mut curve_types: BTreeMap<&str, u64> = BTreeMap::new();
    for c in &model.curves {
        *curve_types.entry(c.type_name()).or_default() += 1;
    }
    let schema = model.schemas.first().cloned().unwrap_or_default();
    let warnings: Vec<String> = model.warnings.iter().map(|w| w.to_string()).collect();
    let geometry_found = !bbox.is_empty() || counts.faces > 0 || counts.products > 0;

    if args.json {
        let out = json!({
            "file": args.file.display().to_string(),
            "bytes": std::fs::metadata(&args.file).map(|m| m.len()).unwrap_or(0),
            "schema": schema,
            "protocol": protocol(&schema),
            "units": {
                "length": model.units.length_name,
                "length_to_mm": model.units.length_to_mm,
                "angle": model.units.angle_name,
                "uncertainty_mm": model.units.uncertainty_mm,
            },
            "faces": counts.faces,
            "shells": counts.shells,
            "solids": counts.solids,
            "products": counts.products,
            "instances": counts.instances,
            "surface_types": counts.surface_types,
            "curve_types": curve_types,
            "entities": loaded.file.len(),
            "entity_types": entity_counts(&loaded.file),
            "bbox": if bbox.is_empty() { serde_json::Value::Null } else { json!(bbox.to_array()) },
            "pmi": pmi_json(&model.pmi),
            "warnings": warnings,
            "parse_seconds": loaded.parse_seconds,
            "map_seconds": loaded.map_seconds,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let u = &model.units;
        println!("file       {}", args.file.display());
        println!("schema     {schema} ({})", protocol(&schema));
        println!(
            "units      {} (×{} mm), {}{}",
            u.length_name,
            u.length_to_mm,
            u.angle_name,
            u.uncertainty_mm
                .map(|x| format!(", uncertainty {x:e} mm"))
                .unwrap_or_default()
        );
        println!(
            "topology   {} solids, {} shells, {} faces",
            counts.solids, counts.shells, counts.faces
        );
        println!(
            "assembly   {} products, {} part instances",
            counts.products, counts.instances
        );
        if bbox.is_empty() {
            println!("bbox       (no geometry)");
        } else {
            let s = bbox.max - bbox.min;
            println!(
                "bbox (mm)  [{:.4}, {:.4}, {:.4}] – [{:.4}, {:.4}, {:.4}]  size {:.4} × {:.4} × {:.4}",
                bbox.min.x,
                bbox.min.y,
                bbox.min.z,
                bbox.max.x,
                bbox.max.y,
                bbox.max.z,
                s.x,
                s.y,
                s.z
            );
        }
        let list = |m: &BTreeMap<_, u64>| {
            m.iter()
                .map(|(k, v)| format!("{k} {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "surfaces   {}",
            list(
                &counts
                    .surface_types
                    .iter()
                    .map(|(k, v)| (k.as_str(), *v))
                    .collect()
            )
        );
        println!("curves     {}", list(&curve_types));
        let mut entities: Vec<(String, u64)> = entity_counts(&loaded.file).into_iter().collect();
        entities.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        println!(
            "entities   {} instances; most used: {}",
            loaded.file.len(),
            entities
                .iter()
                .take(12)
                .map(|(k, v)| format!("{k} {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        println!("product tree");
        let mut lines = Vec::new();
        for &root in &model.roots {
            tree_lines(model, root, 0, 1, &mut lines);
        }
        for l in &lines {
            println!("{l}");
        }
        println!("warnings   {}", warnings.len());
        for w in warnings.iter().take(args.max_warnings) {
            println!("  {w}");
        }
        if warnings.len() > args.max_warnings {
            println!(
                "  … {} more (see --json)",
                warnings.len() - args.max_warnings
            );
        }
        if args.faces {
            print_faces(model, args.edges);
        }
        println!(
            "time       parse {:.3} s, map {:.3} s",
            loaded.parse_seconds, loaded.map_seconds
        );
    }
    if !geometry_found {
        anyhow::bail!(
            "{}: no geometry could be read ({} warnings)",
            args.file.display(),
            warnings.len()
        );
    }
    Ok(())
}
