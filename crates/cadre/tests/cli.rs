//! The `cadre` command line, run as a user runs it.

use std::process::Command;

#[path = "../../cadre-step/tests/common/hostile.rs"]
mod hostile;

fn cadre() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cadre"))
}

/// An empty folder of this test process's own under the system's temporary folder.
fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../examples/pin-assembly.step"
);

#[test]
fn info_json_reports_the_bundled_assembly() {
    let out = cadre().args(["info", "--json", EXAMPLE]).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["faces"], 6);
    assert_eq!(v["shells"], 2);
    assert_eq!(v["solids"], 2);
    assert_eq!(v["products"], 2);
    assert_eq!(v["instances"], 2);
    assert_eq!(v["surface_types"]["Cylinder"], 2);
    assert_eq!(v["surface_types"]["Plane"], 4);
    assert_eq!(v["protocol"], "AP214");
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0));
    let bbox: Vec<f64> = v["bbox"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let want = [-5.0, -5.0, -5.0, 25.0, 40.0, 10.0];
    assert!(
        bbox.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6),
        "{bbox:?}"
    );
}

#[test]
fn info_human_summary_shows_the_tree_and_faces() {
    let out = cadre().args(["info", "--faces", EXAMPLE]).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("pin assembly"), "{text}");
    assert!(text.contains("pin ×2"), "{text}");
    assert!(text.contains("Cylinder"), "{text}");
}

#[test]
fn missing_and_non_step_files_fail_with_a_message() {
    let out = cadre()
        .args(["info", "/nonexistent/file.step"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/file.step"));

    let dir = scratch_dir("cadre-cli");
    let junk = dir.join("junk.step");
    std::fs::write(&junk, b"this is not an exchange structure").unwrap();
    let out = cadre().arg("info").arg(&junk).output().unwrap();
    assert!(!out.status.success());
    assert!(!String::from_utf8_lossy(&out.stderr).trim().is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

/// With `RUST_BACKTRACE=1` (common on developer machines) a user's mistake is still one
/// message, not a 20-frame backtrace; the error and its causes, exit status 1.
#[test]
fn user_errors_print_no_backtrace() {
    let out = cadre()
        .env("RUST_BACKTRACE", "1")
        .args(["info", "/nonexistent/file.step"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("Error: "), "{err}");
    assert!(
        !err.contains("Stack backtrace") && !err.contains("backtrace"),
        "{err}"
    );
}

/// `--supersample` takes 1 to 4, as its help says; 0 and 9 are refused before any work.
#[test]
fn supersample_outside_its_range_is_refused() {
    for bad in ["0", "9"] {
        let out = cadre()
            .args([
                "render",
                EXAMPLE,
                "-o",
                "/tmp/never.png",
                "--supersample",
                bad,
            ])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--supersample {bad}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("supersample"));
    }
}

/// A wrong output path fails before any work and leaves no file: an unsupported extension
/// (`x.jpg` used to be left as a 0-byte file), a folder that does not exist.
#[test]
fn bad_output_paths_fail_first_and_leave_nothing() {
    let dir = scratch_dir("cadre-out");
    let jpg = dir.join("x.jpg");
    let out = cadre()
        .args(["render", EXAMPLE, "-o"])
        .arg(&jpg)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains(".png"));
    assert!(!jpg.exists());
    let nowhere = dir.join("missing/x.glb");
    let out = cadre()
        .args(["mesh", EXAMPLE, "-o"])
        .arg(&nowhere)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not exist"));
    let out = cadre()
        .args(["mesh", EXAMPLE, "-o"])
        .arg(dir.join("x.ply"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(!dir.join("x.ply").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Negative numbers reach cadre's own checks (clap took `-5` for a flag and said
/// "unexpected argument"), which name the option and what it takes.
#[test]
fn negative_numbers_get_the_options_own_message() {
    let cases: [(&[&str], &str); 3] = [
        (
            &["render", EXAMPLE, "-o", "/tmp/never.png", "--size", "-5x5"],
            "1 to 16384",
        ),
        (
            &[
                "render",
                EXAMPLE,
                "-o",
                "/tmp/never.png",
                "--edge-width",
                "-2",
            ],
            "--edge-width",
        ),
        (
            &[
                "mesh",
                EXAMPLE,
                "-o",
                "/tmp/never.glb",
                "--deflection",
                "-1",
            ],
            "positive",
        ),
    ];
    for (args, needle) in cases {
        let out = cadre().args(args).output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(needle) && !err.contains("unexpected argument"),
            "{err}"
        );
    }
}

/// A reader that stops early (`cadre info … | head`) must not make cadre print a panic.
#[test]
fn closed_output_pipe_ends_quietly() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/corpus/step/bug33398.step");
    if !file.is_file() {
        eprintln!("skipping: ../shared/corpus not found (needs a file with a long face list)");
        return;
    }
    let mut child = cadre()
        .args(["info", "--faces", "--edges"])
        .arg(&file)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("cadre runs");
    let mut first = [0u8; 16];
    std::io::Read::read_exact(child.stdout.as_mut().expect("stdout"), &mut first).expect("output");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("cadre ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        matches!(out.status.code(), Some(0 | 141)),
        "{:?}",
        out.status
    );
}

#[test]
fn render_writes_a_png_of_the_asked_size_and_refuses_bad_options() {
    let dir = scratch_dir("cadre-render");
    let out = dir.join("pin.png");
    let run = cadre()
        .args(["render", EXAMPLE, "-o"])
        .arg(&out)
        .args([
            "--size",
            "64x48",
            "--view",
            "top",
            "--ortho",
            "--background",
            "#102030",
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let image = std::fs::read(&out).unwrap();
    // PNG signature, then the IHDR chunk's width and height.
    assert_eq!(&image[..8], b"\x89PNG\r\n\x1a\n");
    let be = |i: usize| u32::from_be_bytes([image[i], image[i + 1], image[i + 2], image[i + 3]]);
    assert_eq!((be(16), be(20)), (64, 48));
    for bad in [
        ["--size", "0x10"],
        ["--view", "sideways"],
        ["--background", "#12"],
        ["--antialias", "fxaa"],
    ] {
        let run = cadre()
            .args(["render", EXAMPLE, "-o"])
            .arg(&out)
            .args(bad)
            .output()
            .unwrap();
        assert!(!run.status.success(), "{bad:?} accepted");
    }
    // A folder in, a folder out.
    let folder = dir.join("in");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(EXAMPLE, folder.join("a.step")).unwrap();
    let run = cadre()
        .args(["render"])
        .arg(&folder)
        .arg("-o")
        .arg(dir.join("out"))
        .args(["--size", "32x32", "--sheet"])
        .arg(dir.join("sheet.png"))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(dir.join("out/a.png").is_file());
    assert!(dir.join("sheet.png").is_file());
    let index = std::fs::read_to_string(dir.join("sheet.txt")).unwrap();
    assert!(
        index.starts_with("row 1 column 1: ") && index.contains("a.step"),
        "{index}"
    );
    // A file with nothing to draw is an error, with the reason, and leaves no image (a
    // blank one looked like a result); `cadre mesh` of it writes no empty GLB either.
    let empty = dir.join("empty.step");
    std::fs::write(
        &empty,
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('e','',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n\
         #1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\nEND-ISO-10303-21;\n",
    )
    .unwrap();
    let run = cadre()
        .args(["render"])
        .arg(&empty)
        .arg("-o")
        .arg(dir.join("empty.png"))
        .args(["--size", "16x16"])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("nothing to draw"));
    assert!(!dir.join("empty.png").exists());
    let run = cadre()
        .args(["mesh", "--json"])
        .arg(&empty)
        .arg("-o")
        .arg(dir.join("empty.glb"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("nothing to write"));
    assert!(!dir.join("empty.glb").exists());
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(report["empty"], true);
    assert_eq!(report["triangles"], 0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_without_a_session_prints_no_error_lines() {
    // Without XDG_RUNTIME_DIR (CI, cron, ssh), Mesa's device-selection layer made libwayland
    // print "error: XDG_RUNTIME_DIR is invalid or not set" twice per run (issue 12). A clean
    // render of the example prints only its "wrote" line and no warning.
    let dir = scratch_dir("cadre-quiet");
    let out = dir.join("pin.png");
    let run = cadre()
        .args(["render", EXAMPLE, "--size", "32x24", "-o"])
        .arg(&out)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        !stderr.to_lowercase().contains("error"),
        "a successful render printed an error line: {stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mesh_json_lists_warnings_and_what_the_mesh_lost() {
    let run = cadre().args(["mesh", EXAMPLE, "--json"]).output().unwrap();
    assert!(run.status.success());
    let j: serde_json::Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
    for key in [
        "warnings",
        "mesh_warnings",
        "failed_faces",
        "repaired_faces",
        "truncated_faces",
        "open_shells",
    ] {
        assert!(j[key].is_array(), "{key} missing: {j}");
    }
    // The bundled assembly meshes whole and closed.
    assert_eq!(j["open_shells"].as_array().unwrap().len(), 0, "{j}");
    assert_eq!(j["failed_faces"].as_array().unwrap().len(), 0, "{j}");
}

/// `wide6.step` of issue 13 (six levels of ten uses: 2·10⁶ cube instances in 42 KB, every
/// use shifted along the same axis) is drawn by instancing (10³ draw records, not 2·10⁶) but
/// piles its cubes about 10⁴ times over every pixel: `render` refuses it before drawing,
/// with the reason, and writes no image (it once panicked inside wgpu after 1.9 GB); three
/// levels (10³ instances) render (negative control). Skipped when `../shared` is absent.
#[test]
fn render_refuses_a_scene_piled_past_the_fill_bound() {
    let (Some(wide), Some(small)) = (hostile::chain(6, 10), hostile::chain(3, 10)) else {
        return;
    };
    let dir = scratch_dir("cadre-wide");
    std::fs::write(dir.join("wide6.step"), wide).unwrap();
    std::fs::write(dir.join("wide3.step"), small).unwrap();
    let render = |name: &str| {
        cadre()
            .arg("render")
            .arg(dir.join(format!("{name}.step")))
            .arg("-o")
            .arg(dir.join(format!("{name}.png")))
            .args(["--size", "32x24"])
            .output()
            .unwrap()
    };
    let run = render("wide6");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("times over, past the 1000 one frame draws")
            && stderr.contains("nothing was drawn"),
        "{stderr}"
    );
    assert!(!dir.join("wide6.png").exists());
    let run = render("wide3");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(dir.join("wide3.png").is_file());
}

/// Six levels of 13 uses expand to 9.7·10⁶ part instances (under the mapper's 5·10⁷ cap), more than the 4·10⁶ nodes a
/// scene holds: `mesh -o` refuses before meshing (the scene was cut there silently) and
/// writes nothing; `mesh --json` (no scene) still measures. Skipped when `../shared` is absent.
#[test]
fn mesh_refuses_an_assembly_wider_than_a_scene_holds() {
    let Some(wide) = hostile::chain(6, 13) else {
        return;
    };
    let dir = scratch_dir("cadre-wide13");
    let input = dir.join("wide13.step");
    std::fs::write(&input, wide).unwrap();
    let out = dir.join("wide13.glb");
    let run = cadre()
        .arg("mesh")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("over the 4000000 one export holds"),
        "{stderr}"
    );
    assert!(!out.exists());
    // Negative control: measuring needs no scene and goes through.
    let run = cadre()
        .args(["mesh", "--json"])
        .arg(&input)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

#[test]
fn every_antialiasing_choice_renders_and_smoothing_changes_the_image() {
    let dir = scratch_dir("cadre-antialias");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let run = cadre()
            .args([
                "render",
                EXAMPLE,
                "--size",
                "96x72",
                "--mode",
                "shaded-edges",
                "-o",
            ])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        image::open(&out).unwrap().to_rgba8()
    };
    let none = render("none.png", &["--antialias", "none"]);
    let smooth = render("smooth.png", &["--antialias", "smooth"]);
    let supersampled = render(
        "ss.png",
        &["--antialias", "supersample", "--supersample", "3"],
    );
    let default = render("default.png", &[]);
    assert_ne!(none, smooth, "smoothing changed nothing");
    assert_ne!(none, supersampled, "supersampling changed nothing");
    // The default is one of the two anti-aliased images, never the aliased one.
    assert_ne!(default, none, "the default is not anti-aliased");
    // `--supersample 1` alone is an explicit choice of one sample: the aliased image.
    assert_eq!(render("one.png", &["--supersample", "1"]), none);
}

#[test]
fn render_draws_a_scene_file_and_names_the_bad_line_or_object() {
    let dir = scratch_dir("cadre-render-scene");
    let teapot = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/teapot.json"
    );
    let out = dir.join("teapot.png");
    let run = cadre()
        .args(["render", teapot, "--size", "64x48", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("10 quadric(s) ray cast"), "{stderr}");
    let image = image::open(&out).unwrap().to_rgba8();
    assert_eq!(image.dimensions(), (64, 48));
    // Not a blank image: the teapot covers part of it.
    let background = *image.get_pixel(0, 0);
    assert!(image.pixels().filter(|p| **p != background).count() > 200);
    // An object the planes leave open is named and left out; a malformed file names its line.
    let scene = dir.join("open.json");
    std::fs::write(
        &scene,
        r#"{"objects": [{"shape": {"sphere": 1}}, {"shape": {"cylinder": 1}}]}"#,
    )
    .unwrap();
    let run = cadre()
        .args(["render"])
        .arg(&scene)
        .args(["--size", "32x24", "-o"])
        .arg(dir.join("open.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("object 1: the primitive is unbounded"),
        "{stderr}"
    );
    std::fs::write(&scene, "{\n\"objects\": [\n{\"shape\": 7}\n]}").unwrap();
    let run = cadre()
        .args(["render"])
        .arg(&scene)
        .args(["--size", "32x24", "-o"])
        .arg(dir.join("bad.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(stderr.contains("line 3"), "{stderr}");
    assert!(!dir.join("bad.png").exists());
}

const PLATE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../examples/toolpath/plate.step"
);
const PLATE_PROGRAM: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../examples/toolpath/plate.ngc"
);

#[test]
fn toolpath_json_lists_the_example_program_moves() {
    let out = cadre()
        .args(["toolpath", "--json", PLATE_PROGRAM])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["units"], "mm");
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0), "{v}");
    let moves = v["moves"].as_array().unwrap();
    assert!(moves.len() > 100, "{}", moves.len());
    // The first move: G0 Z20 on line 13, from the machine's origin.
    assert_eq!(moves[0]["kind"], "rapid");
    assert_eq!(moves[0]["end"], serde_json::json!([0.0, 0.0, 20.0]));
    // Arcs carry their centre and signed turns; the profile's corners are clockwise
    // quarter turns.
    let corner = moves.iter().find(|m| m["kind"] == "arc").expect("an arc");
    assert_eq!(corner["turns"], -0.25);
    assert!(corner["centre"].is_array());
    // The summary.
    let out = cadre().args(["toolpath", PLATE_PROGRAM]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("tools: [1, 2, 3]"), "{text}");
    assert!(text.contains("warnings: 0"), "{text}");
}

#[test]
fn toolpath_warns_bad_lines_with_their_numbers_and_loads_the_rest() {
    let dir = scratch_dir("cadre-toolpath-bad");
    let program = dir.join("bad.ngc");
    std::fs::write(&program, "G0 X1\nG1 X[2 +\nG5.2 X3 Y3\nG1 X4 F100\n").unwrap();
    let out = cadre()
        .args(["toolpath", "--json"])
        .arg(&program)
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let lines: Vec<u64> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["line"].as_u64().unwrap())
        .collect();
    assert_eq!(lines, [2, 3], "{v}");
    assert_eq!(v["moves"].as_array().unwrap().len(), 3);
    let out = cadre()
        .args(["toolpath", "/nonexistent/x.ngc"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("x.ngc"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_draws_a_toolpath_over_its_part_and_alone() {
    let dir = scratch_dir("cadre-toolpath-render");
    let over = dir.join("over.png");
    let out = cadre()
        .args([
            "render",
            PLATE,
            "--toolpath",
            PLATE_PROGRAM,
            "--size",
            "200x150",
        ])
        .args(["--up-to", "1500", "--clip-box", "-10,-10,-5,90,60,30", "-o"])
        .arg(&over)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = image::open(&over).unwrap().to_rgba8();
    assert_eq!(image.dimensions(), (200, 150));
    // Coloured (not grey) pixels: the path's feed colours.
    let coloured = image
        .pixels()
        .filter(|p| p[0].abs_diff(p[1]) > 60 || p[1].abs_diff(p[2]) > 60)
        .count();
    assert!(coloured > 100, "{coloured}");
    let alone = dir.join("alone.png");
    let out = cadre()
        .args(["render", PLATE_PROGRAM, "--size", "200x150", "-o"])
        .arg(&alone)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(alone.is_file());
    let out = cadre()
        .args([
            "render",
            PLATE,
            "--toolpath",
            PLATE_PROGRAM,
            "--up-to",
            "-3",
            "-o",
        ])
        .arg(dir.join("never.png"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_labels_the_parts_with_callouts() {
    let dir = scratch_dir("cadre-labels");
    let render = |extra: &[&str], name: &str| {
        let path = dir.join(name);
        let out = cadre()
            .args(["render", EXAMPLE, "--size", "300x200"])
            .args(extra)
            .arg("-o")
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        image::open(&path).unwrap().to_rgba8()
    };
    let labelled = render(&["--labels"], "labelled.png");
    let bare = render(&[], "bare.png");
    // The label boxes' pale yellow appears only with --labels.
    let boxes = |i: &image::RgbaImage| {
        i.pixels()
            .filter(|p| p[0] > 240 && p[1] > 240 && p[2] > 190 && p[2] < 235)
            .count()
    };
    assert!(boxes(&labelled) > 200, "{}", boxes(&labelled));
    assert_eq!(boxes(&bare), 0);
    let out = cadre()
        .args(["render", EXAMPLE, "--labels", "--label-size", "0", "-o"])
        .arg(dir.join("never.png"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--label-size"));
    let _ = std::fs::remove_dir_all(&dir);
}

const PMI_BLOCK: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../examples/pmi/block-pmi.step"
);

#[test]
fn pmi_is_listed_drawn_and_its_saved_view_rendered() {
    let out = cadre()
        .args(["info", "--json", PMI_BLOCK])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pmi = &v["pmi"];
    assert_eq!(pmi["annotations"], 1);
    assert_eq!(pmi["dimensions"], 1);
    assert_eq!(pmi["tolerances"], 1);
    assert_eq!(pmi["datums"], 1);
    assert_eq!(pmi["datum_targets"], 0);
    assert_eq!(pmi["saved_views"], serde_json::json!(["Top"]));
    // The semantic items as their frames write them, with their faces.
    let items = pmi["semantic"].as_array().expect("semantic items");
    assert_eq!(items.len(), 3);
    let text = |t: &str| {
        items
            .iter()
            .find(|i| i["type"] == t)
            .and_then(|i| i["text"].as_str().map(str::to_string))
            .unwrap_or_default()
    };
    assert!(text("tolerance").contains("0.05"), "{}", text("tolerance"));
    assert_eq!(text("datum"), "A");
    assert!(items.iter().all(|i| i["faces"].as_u64() > Some(0)));
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0));
    let dir = scratch_dir("cadre-pmi");
    let render = |extra: &[&str], name: &str| {
        let path = dir.join(name);
        let out = cadre()
            .args([
                "render",
                PMI_BLOCK,
                "--size",
                "480x360",
                "--antialias",
                "none",
            ])
            .args(extra)
            .arg("-o")
            .arg(&path)
            .output()
            .unwrap();
        (out, path)
    };
    // The callout is green (its curve style), the generated callouts dark blue.
    let green = |i: &image::RgbaImage| {
        i.pixels()
            .filter(|p| p[1] > p[0].saturating_add(25) && p[1] > p[2].saturating_add(15))
            .count()
    };
    let (out, path) = render(&["--pmi"], "pmi.png");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("2 semantic PMI item(s)"));
    let with = image::open(&path).unwrap().to_rgba8();
    let (out, path) = render(&[], "bare.png");
    assert!(out.status.success());
    let without = image::open(&path).unwrap().to_rgba8();
    assert!(green(&with) > 50, "{}", green(&with));
    assert_eq!(green(&without), 0);
    let (out, path) = render(&["--saved-view", "top"], "top.png");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(green(&image::open(&path).unwrap().to_rgba8()) > 50);
    let (out, _) = render(&["--saved-view", "side"], "never.png");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no saved view \"side\"") && err.contains("Top"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_draws_the_dimensions_kept_beside_the_file() {
    let dir = scratch_dir("cadre-dimensions");
    let model = dir.join("block.step");
    std::fs::copy(PMI_BLOCK, &model).unwrap();
    let out_png = dir.join("d.png");
    let run = || {
        cadre()
            .args([
                "render",
                "--dimensions",
                "--size",
                "320x240",
                "--antialias",
                "none",
            ])
            .arg(&model)
            .arg("-o")
            .arg(&out_png)
            .output()
            .unwrap()
    };
    // No file beside it: a clear error.
    let out = run();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no dimensions kept beside it"));
    // A distance across the block's top, drawn in the dimension colour.
    std::fs::write(
        dir.join("block.step.dimensions.json"),
        r#"{"dimensions": [{"kind": "distance", "value": 60.0, "text": "60.000 mm",
            "points": [[0, 0, 10], [60, 0, 10]]}]}"#,
    )
    .unwrap();
    let out = run();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let brown = || {
        let image = image::open(&out_png).unwrap().to_rgba8();
        image
            .pixels()
            .filter(|p| {
                p[0] > 120 && p[0] > p[1].saturating_add(40) && p[1] > p[2].saturating_add(20)
            })
            .count()
    };
    let distance_only = brown();
    assert!(distance_only > 40, "{distance_only}");
    // A radius (centre to circle, centre mark), an angle (arc and legs) and a length
    // (along its edge) draw their own lines: more of the colour. Their points without a
    // shape (a radius of one point) draw nothing more (the negative control).
    let write = |more: &str| {
        std::fs::write(
            dir.join("block.step.dimensions.json"),
            format!(
                r#"{{"dimensions": [{{"kind": "distance", "value": 60.0, "text": "60.000 mm",
                "points": [[0, 0, 10], [60, 0, 10]]}}{more}]}}"#
            ),
        )
        .unwrap();
    };
    write(
        r#", {"kind": "radius", "value": 10, "text": "R10.000 mm",
            "points": [[30, 20, 10], [40, 20, 10], [30, 20, 11]]},
           {"kind": "angle", "value": 1.5708, "text": "90.000°",
            "points": [[60, 0, 10], [52, 0, 10], [60, 0, 2]]},
           {"kind": "length", "value": 60, "text": "60.000 mm",
            "points": [[0, 40, 10], [20, 40, 10], [40, 40, 10], [60, 40, 10]]}"#,
    );
    assert!(run().status.success());
    let all_kinds = brown();
    write(r#", {"kind": "radius", "value": 10, "text": "", "points": [[30, 20, 10]]}"#);
    assert!(run().status.success());
    let shapeless = brown();
    assert!(
        all_kinds > distance_only + 200 && shapeless < distance_only + 20,
        "distance {distance_only}, all kinds {all_kinds}, a shapeless radius {shapeless}"
    );
    // A file that is not one: the error names it.
    std::fs::write(dir.join("block.step.dimensions.json"), "[1, 2]").unwrap();
    let out = run();
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a dimension file"));
    let _ = std::fs::remove_dir_all(&dir);
}
