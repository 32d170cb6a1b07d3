//! `cadre verify`: the face-id image of a file's views, drawn by the mesh or the trim
//! back-end, against the CPU ray caster of the exact B-Rep (`cadre_render::raycast`), at
//! several magnifications: so anyone can check any file.

use std::collections::HashSet;
use std::path::PathBuf;

use anyhow::{Context, Result};
use cadre_mesh::{Deflection, MeshParams, deflection_diagonal, mesh_model};
use cadre_render::raycast::RayCaster;
use cadre_render::{
    Camera, CrackMode, CrackOptions, FrameOptions, Gpu, RenderScene, ViewPreset, ViewState,
};
use serde_json::json;

use crate::commands::render::{
    CrackArg, CrackArgs, Method, centre_point, parse_size, view_trim_tolerance, with_trims,
};
use crate::load::load_step;

/// Arguments of `cadre verify`.
#[derive(clap::Args)]
pub struct VerifyArgs {
    /// A STEP file.
    input: PathBuf,
    /// How faces are drawn (as `cadre render --method`).
    #[arg(long, default_value = "trim", value_enum)]
    method: Method,
    /// Magnifications, comma-separated (as `cadre render --zoom`, about the model point at
    /// the centre of each view).
    #[arg(long, default_value = "1,10,100,1000", value_delimiter = ',')]
    zoom: Vec<f64>,
    /// Image size, WIDTHxHEIGHT (the ray caster casts nine rays a pixel).
    #[arg(long, default_value = "160x120", value_parser = parse_size)]
    size: (u32, u32),
    /// Tolerance of the trims, relative to the bounding-box diagonal, at most (each zoom's
    /// trims are fitted within a quarter of its pixel where that is finer, as `cadre render
    /// --zoom` fits them).
    #[arg(long, default_value_t = 1e-5)]
    trim_tolerance_rel: f64,
    /// Also count, per view, the crack pixels against the ray caster's image with the crack
    /// pass off ("cracks_before") and in this mode ("cracks_after"); the comparison is of
    /// the image in this mode. Without it the image is drawn as `cadre render` draws it
    /// (exact crack fill) and no crack figures are given.
    #[arg(long, value_enum)]
    cracks: Option<CrackArg>,
    /// Gaps in the model narrower than this (model units) are closed (as `cadre render
    /// --gap-tolerance`).
    #[arg(long, default_value_t = 0.0)]
    gap_tolerance: f64,
    /// d_min of the crack detection and of the crack count, model units; 0 takes 10⁻³ of
    /// the model's diagonal.
    #[arg(long, default_value_t = 0.0)]
    crack_depth: f64,
    /// The exact fill leaves the pixels beside silhouettes as drawn (the seed's rule
    /// alone, as `cadre render --no-silhouette-fill`).
    #[arg(long)]
    no_silhouette_fill: bool,
    /// One JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Print each disagreeing pixel on stderr with the face ids around it, both images
    /// side by side (the GPU's on the left).
    #[arg(long)]
    explain: bool,
}

/// The views each magnification is checked in.
const VIEWS: [(&str, ViewPreset); 4] = [
    ("iso", ViewPreset::Iso),
    ("front", ViewPreset::Front),
    ("top", ViewPreset::Top),
    ("right", ViewPreset::Right),
];

/// Farthest distance, in pixels, a disagreeing pixel is looked at for the face it shows.
const SEARCH_PX: i64 = 16;

/// The ray caster's trim tolerance relative to the diagonal at the zooms whose pixel is
/// coarser than four times it.
const CASTER_TRIM_REL: f64 = 1e-4;

/// One view's figures.
struct ViewFigures {
    /// Share of the compared pixels that disagree farther than 0.5 px from a true boundary.
    disagree_share: f64,
    /// Largest distance (pixels) from a disagreeing pixel to where the ray caster sees the
    /// face the GPU drew there ([`SEARCH_PX`] + 1 when farther).
    worst_px: f64,
    /// The same for pixels where one side sees the background and the other a face.
    silhouette_px: f64,
    /// Share of the covered pixels left out: they show faces the ray caster cannot cast.
    unverified_share: f64,
    /// Pixels compared.
    compared: usize,
    /// Crack pixels against the ray caster's image with the crack pass off and on (with
    /// `--cracks`).
    cracks: Option<(usize, usize)>,
}

/// Runs `cadre verify`.
pub fn run(args: &VerifyArgs) -> Result<()> {
    let input = args.input.as_path();
    let loaded = load_step(input)?;
    let model = &loaded.model;
    let params = MeshParams {
        deflection: Deflection::Relative(0.0005).resolve(deflection_diagonal(model)),
        angle: 0.35,
        ..MeshParams::default()
    };
    let mesh = mesh_model(model, &params, None);
    let gpu = Gpu::headless().context("no GPU adapter")?;
    let renderer = args.method.renderer(&gpu)?;
    let scene = RenderScene::from_model(model, &mesh);
    let (lo, hi) = scene
        .bounds()
        .with_context(|| format!("{}: nothing to draw", input.display()))?;
    let (w, h) = args.size;
    // The ray caster's trim polygons follow the trim curves within 10⁻⁴ of the diagonal, or
    // a quarter of the view's pixel where that is finer (`view_trim_tolerance`): at 1000× a
    // 160-pixel view's pixel is 6·10⁻⁶ of the model, and polygons within 10⁻⁴ put the
    // oracle's own trimmed edges 16 pixels off the true curves.
    let diagonal = (hi - lo).length();
    let caster_at = |zoom: f64| {
        let relative = view_trim_tolerance(CASTER_TRIM_REL, (w, h), zoom);
        (relative, RayCaster::new(model, relative * diagonal))
    };
    let mut caster = caster_at(1.0);
    let skipped: HashSet<u64> = caster.1.skipped.iter().copied().collect();
    let crack_args = CrackArgs {
        cracks: args.cracks.unwrap_or(CrackArg::Exact),
        inspect_cracks: false,
        gap_tolerance: args.gap_tolerance,
        crack_depth: args.crack_depth,
        no_silhouette_fill: args.no_silhouette_fill,
    };
    let options = FrameOptions {
        width: w,
        height: h,
        supersample: 1,
        cracks: crack_args.options(),
        ..FrameOptions::default()
    };
    let no_cracks = FrameOptions {
        cracks: CrackOptions {
            mode: CrackMode::Off,
            ..options.cracks
        },
        ..options.clone()
    };
    // The crack count's d_min: the crack pass's own.
    let d_min = if args.crack_depth > 0.0 {
        args.crack_depth
    } else {
        cadre_render::CRACK_MIN_DEPTH_REL * diagonal
    };
    // Each zoom drawn with the trims `cadre render --zoom` would fit for it (within a quarter
    // of its pixel, `view_trim_tolerance`); the faces left to their meshes are the same at
    // every tolerance but the finest's are kept.
    let mut fallback: Vec<u64> = Vec::new();
    let mut by_zoom = Vec::new();
    for &zoom in &args.zoom {
        if view_trim_tolerance(CASTER_TRIM_REL, (w, h), zoom) != caster.0 {
            caster = caster_at(zoom);
        }
        let caster = &caster.1;
        let scene = if args.method.exact() {
            let relative = view_trim_tolerance(args.trim_tolerance_rel, (w, h), zoom);
            with_trims(&renderer, scene.clone(), model, relative, input)
        } else {
            scene.clone()
        };
        fallback = scene
            .trim
            .as_ref()
            .map_or_else(Vec::new, |t| t.fallback.iter().map(|(id, _)| *id).collect());
        let prepared = renderer.prepare(&gpu, &scene);
        for (name, preset) in VIEWS {
            let fitted = Camera::fit(lo, hi, preset, false, f64::from(w) / f64::from(h));
            let point = centre_point(caster, &fitted, (lo, hi));
            let camera = fitted.zoomed_at(point, zoom, (lo, hi));
            let ids =
                renderer.render_ids(&gpu, &prepared, &camera, &options, &ViewState::default())?;
            let gpu_ids: Vec<u64> = ids.iter().map(|p| scene.face_step_id(p[0])).collect();
            let hits = caster.hits(&camera, w, h);
            let exact: Vec<u64> = hits.iter().map(|h| h.map_or(0, |(id, _)| id)).collect();
            let mut near = caster.near_boundary(&camera, w, h, 0.5);
            // The pixels that would count as wrong looked at again, closely: eight samples
            // on a circle miss a sub-pixel sliver.
            let suspects: Vec<usize> = (0..near.len())
                .filter(|&i| !near[i] && gpu_ids[i] != exact[i])
                .collect();
            let dense = caster.near_boundary_at(&camera, (w, h), 0.5, &suspects);
            for (&i, d) in suspects.iter().zip(dense) {
                near[i] = d;
            }
            let mut figures = compare_view((&gpu_ids, &exact, &near), (w, h), &skipped);
            if args.cracks.is_some() {
                let before = renderer.render_ids(
                    &gpu,
                    &prepared,
                    &camera,
                    &no_cracks,
                    &ViewState::default(),
                )?;
                let before_ids: Vec<u64> =
                    before.iter().map(|p| scene.face_step_id(p[0])).collect();
                let cracks = |ids: &[[u32; 4]], step_ids: &[u64]| {
                    caster.crack_pixels(&camera, (w, h), (ids, step_ids, &hits), d_min)
                };
                let (before, after) = (cracks(&before, &before_ids), cracks(&ids, &gpu_ids));
                if args.explain {
                    for &i in &after {
                        let (x, y) = (i as u32 % w, i as u32 / w);
                        eprintln!(
                            "{name} {zoom}x: crack left at ({x}, {y}): the GPU shows {:?}, \
                             the ray caster face #{}",
                            ids[i], exact[i]
                        );
                        print_neighbourhood(i, (&gpu_ids, &exact), (w, h));
                    }
                }
                figures.cracks = Some((before.len(), after.len()));
            }
            if args.explain {
                explain(name, zoom, (&gpu_ids, &exact, &near), (w, h), &skipped);
            }
            by_zoom.push((name, zoom, figures));
        }
    }
    // View by view, each at every zoom (the order the output always had).
    by_zoom.sort_by_key(|v| VIEWS.iter().position(|(name, _)| *name == v.0));
    let views = by_zoom;
    if args.json {
        let views: Vec<serde_json::Value> = views
            .iter()
            .map(|(view, zoom, f)| {
                json!({
                    "view": view,
                    "zoom": zoom,
                    "disagree_share": f.disagree_share,
                    "worst_px": f.worst_px,
                    "silhouette_px": f.silhouette_px,
                    "unverified_share": f.unverified_share,
                    "compared": f.compared,
                    "cracks_before": f.cracks.map(|c| c.0),
                    "cracks_after": f.cracks.map(|c| c.1),
                })
            })
            .collect();
        println!(
            "{}",
            json!({
                "file": input.display().to_string(),
                "method": format!("{:?}", args.method).to_lowercase(),
                "faces": model.faces.len(),
                "fallback_faces": fallback,
                "uncast_faces": caster.1.skipped,
                "views": views,
            })
        );
    } else {
        println!(
            "{}: {} faces, {} drawn from their meshes, {} the ray caster cannot cast",
            input.display(),
            model.faces.len(),
            fallback.len(),
            caster.1.skipped.len()
        );
        println!(
            "view   zoom  disagree  worst px  silhouette px  unverified  cracks before → after"
        );
        for (view, zoom, f) in &views {
            println!(
                "{view:<6} {zoom:>5}  {:>7.3} %  {:>8.1}  {:>13.1}  {:>8.1} %  {}",
                100.0 * f.disagree_share,
                f.worst_px,
                f.silhouette_px,
                100.0 * f.unverified_share,
                f.cracks
                    .map_or_else(|| "-".to_string(), |(b, a)| format!("{b} → {a}"))
            );
        }
    }
    Ok(())
}

/// One view's figures from the GPU's and the ray caster's face ids (STEP ids, 0 for the
/// background) and the ray caster's near-boundary pixels; pixels showing a face in `skipped`
/// on either side are left out.
fn compare_view(
    (gpu, exact, near): (&[u64], &[u64], &[bool]),
    (w, h): (u32, u32),
    skipped: &HashSet<u64>,
) -> ViewFigures {
    let (w, h) = (i64::from(w), i64::from(h));
    let (mut compared, mut disagree, mut covered, mut unverified) =
        (0usize, 0usize, 0usize, 0usize);
    let (mut worst, mut silhouette) = (0.0f64, 0.0f64);
    for i in 0..gpu.len() {
        let (g, e) = (gpu[i], exact[i]);
        if g == 0 && e == 0 {
            continue;
        }
        covered += 1;
        if skipped.contains(&g) || skipped.contains(&e) {
            unverified += 1;
            continue;
        }
        if near[i] {
            continue;
        }
        compared += 1;
        if g == e {
            continue;
        }
        disagree += 1;
        // How far the ray caster sees what the GPU drew here.
        let (x, y) = (i as i64 % w, i as i64 / w);
        let mut distance = (SEARCH_PX + 1) as f64;
        for dy in -SEARCH_PX..=SEARCH_PX {
            for dx in -SEARCH_PX..=SEARCH_PX {
                let (a, b) = (x + dx, y + dy);
                if a < 0 || b < 0 || a >= w || b >= h {
                    continue;
                }
                let d = ((dx * dx + dy * dy) as f64).sqrt();
                if d < distance && exact[(b * w + a) as usize] == g {
                    distance = d;
                }
            }
        }
        worst = worst.max(distance);
        if g == 0 || e == 0 {
            silhouette = silhouette.max(distance);
        }
    }
    ViewFigures {
        disagree_share: disagree as f64 / compared.max(1) as f64,
        worst_px: worst,
        silhouette_px: silhouette,
        unverified_share: unverified as f64 / covered.max(1) as f64,
        compared,
        cracks: None,
    }
}

/// Prints, for each pixel [`compare_view`] counts as disagreeing, the face ids of the GPU
/// (left) and of the ray caster (right) in the 17 × 13 pixels about it.
fn explain(
    view: &str,
    zoom: f64,
    (gpu, exact, near): (&[u64], &[u64], &[bool]),
    (w, h): (u32, u32),
    skipped: &HashSet<u64>,
) {
    for i in 0..gpu.len() {
        let (g, e) = (gpu[i], exact[i]);
        if g == e || near[i] || skipped.contains(&g) || skipped.contains(&e) {
            continue;
        }
        let (x, y) = (i as u32 % w, i as u32 / w);
        eprintln!("{view} ×{zoom}, pixel ({x}, {y}): GPU face #{g}, ray caster #{e}");
        print_neighbourhood(i, (gpu, exact), (w, h));
    }
}

/// Prints the face ids of the GPU (left) and of the ray caster (right) in the 17 × 13
/// pixels about pixel `i`.
fn print_neighbourhood(i: usize, (gpu, exact): (&[u64], &[u64]), (w, h): (u32, u32)) {
    let (w, h) = (i64::from(w), i64::from(h));
    let (x, y) = (i as i64 % w, i as i64 / w);
    for b in (y - 6).max(0)..(y + 7).min(h) {
        let row = |img: &[u64]| {
            ((x - 8).max(0)..(x + 9).min(w))
                .map(|a| format!("{:>7}", img[(b * w + a) as usize]))
                .collect::<String>()
        };
        eprintln!("{}   |{}", row(gpu), row(exact));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_off_by_three_is_three_pixels_out() {
        // A 16 × 4 image: face 1 on the left half, face 2 on the right; the GPU's boundary
        // three columns to the right of the exact one.
        let (w, h) = (16u32, 4u32);
        let exact: Vec<u64> = (0..w * h).map(|i| if i % w < 8 { 1 } else { 2 }).collect();
        let gpu: Vec<u64> = (0..w * h).map(|i| if i % w < 11 { 1 } else { 2 }).collect();
        let near: Vec<bool> = (0..w * h).map(|i| (i % w == 7) || (i % w == 8)).collect();
        let f = compare_view((&gpu, &exact, &near), (w, h), &HashSet::new());
        assert_eq!(f.worst_px, 3.0);
        assert_eq!(f.silhouette_px, 0.0);
        assert!(
            (f.disagree_share - 8.0 / 56.0).abs() < 1e-12,
            "{}",
            f.disagree_share
        );
        // Negative control: the same images agree everywhere when they are the same.
        let same = compare_view((&exact, &exact, &near), (w, h), &HashSet::new());
        assert_eq!((same.disagree_share, same.worst_px), (0.0, 0.0));
        // Faces the ray caster cannot cast are left out, not counted as wrong.
        let skipped: HashSet<u64> = [1].into_iter().collect();
        let f = compare_view((&gpu, &exact, &near), (w, h), &skipped);
        assert_eq!(f.disagree_share, 0.0);
        assert!(f.unverified_share > 0.5);
    }
}
