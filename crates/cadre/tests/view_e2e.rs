//! End to end: `cadre view` in a virtual X server (Xvfb), driven by real X input events
//! (xdotool) and a simulated spacenavd, its F12 screenshots checked against what each
//! gesture should do. Skipped, with a message, where Xvfb or xdotool is missing (`.ci/run`
//! installs both).

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

use cadre_render::compare::compare;
use cadre_render::{Camera, DisplayMode, FrameOptions, Gpu, Renderer, ViewPreset};
use cadre_spacenav::sim::SimDaemon;
use image::RgbaImage;

/// The window's size (logical = physical pixels on Xvfb).
const W: u32 = 1000;
const H: u32 = 600;

/// Kills the process when dropped (the test may fail half way).
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn have(program: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {program}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Starts Xvfb on a free display; returns it and its name (":N").
fn xvfb() -> (Killed, String) {
    let mut child = Command::new("Xvfb")
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "1024x768x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb starts");
    let mut out = child.stdout.take().expect("stdout");
    let mut number = String::new();
    let mut byte = [0u8; 1];
    while out.read(&mut byte).is_ok_and(|n| n == 1) && byte[0] != b'\n' {
        number.push(byte[0] as char);
    }
    assert!(!number.is_empty(), "Xvfb gave no display number");
    (Killed(child), format!(":{}", number.trim()))
}

/// The viewer under test, with its `--report` lines.
struct Viewer {
    _child: Killed,
    lines: Receiver<String>,
    display: String,
    window: String,
    /// The 3D view's top-left corner in the window (the panels take the rest).
    origin: (u32, u32),
    /// Every line read so far.
    seen: std::cell::RefCell<Vec<String>>,
}

impl Viewer {
    /// Waits for a report line starting with `prefix` (skipping others).
    fn wait_for(&self, prefix: &str) -> String {
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.seen.borrow_mut().push(line.clone());
                    if line.starts_with(prefix) {
                        return line;
                    }
                }
                Err(RecvTimeoutError::Timeout) => {
                    let seen = self.seen.borrow();
                    panic!(
                        "no '{prefix}' from the viewer in 120 s; its last lines: {:?}",
                        &seen[seen.len().saturating_sub(8)..]
                    )
                }
                Err(RecvTimeoutError::Disconnected) => {
                    panic!("the viewer exited before '{prefix}'")
                }
            }
        }
    }

    /// Whether a line starting with `prefix` came already, else waits for one.
    fn saw_or_wait(&self, prefix: &str) -> String {
        let earlier = self
            .seen
            .borrow()
            .iter()
            .find(|l| l.starts_with(prefix))
            .cloned();
        earlier.unwrap_or_else(|| self.wait_for(prefix))
    }

    fn xdotool(&self, args: &[&str]) {
        let status = Command::new("xdotool")
            .args(args)
            .env("DISPLAY", &self.display)
            .status()
            .expect("xdotool runs");
        assert!(status.success(), "xdotool {args:?}");
    }

    fn key(&self, key: &str) {
        self.xdotool(&["key", "--clearmodifiers", key]);
    }

    /// Moves the pointer to pixel (x, y) of the 3D view.
    fn mouse(&self, x: u32, y: u32) {
        let (x, y) = (x + self.origin.0, y + self.origin.1);
        self.xdotool(&[
            "mousemove",
            "--window",
            &self.window,
            &x.to_string(),
            &y.to_string(),
        ]);
    }

    /// F12, then the screenshot it wrote.
    fn screenshot(&self) -> RgbaImage {
        eprintln!("screenshot");
        self.key("F12");
        let line = self.wait_for("screenshot ");
        let path = PathBuf::from(line.trim_start_matches("screenshot ").trim());
        image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgba8()
    }

    /// A preset by its key, once its transition has ended.
    fn preset(&self, key: &str, name: &str) {
        eprintln!("preset {name}");
        self.key(key);
        self.wait_for(&format!("view {name}"));
        self.wait_for("view still");
    }
}

/// A copy of the bundled pin assembly in a scratch folder: the viewer keeps measurements
/// beside the file it opened, and must not write beside the repository's example.
fn example() -> PathBuf {
    static COPY: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    COPY.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("cadre-view-e2e-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        let copy = dir.join("pin-assembly.step");
        std::fs::copy(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pin-assembly.step"),
            &copy,
        )
        .expect("copied");
        copy
    })
    .clone()
}

/// Pixels that are not the white background.
fn coverage(image: &RgbaImage) -> usize {
    image
        .pixels()
        .filter(|p| p.0[..3].iter().any(|&c| c < 235))
        .count()
}

/// Fraction of pixels differing by more than 24 in some channel.
fn differing(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let n = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0.iter()).any(|(x, y)| x.abs_diff(*y) > 24))
        .count();
    n as f64 / f64::from(a.width() * a.height())
}

#[test]
fn the_viewer_opens_a_model_and_follows_mouse_keyboard_and_3d_mouse() {
    if !have("Xvfb") || !have("xdotool") {
        eprintln!(
            "skipped: the viewer's end-to-end test needs Xvfb and xdotool (apt-get install xvfb xdotool; .ci/run installs them)"
        );
        return;
    }
    let shots = tempdir();
    let (_xvfb, display) = xvfb();
    let spnav = shots.join("spnav.sock");
    let daemon = SimDaemon::bind(&spnav).expect("simulated spacenavd");
    let mut child = Command::new(env!("CARGO_BIN_EXE_cadre"))
        .args([
            "view",
            "--report",
            "--size",
            &format!("{W}x{H}"),
            "--screenshot-dir",
        ])
        .arg(&shots)
        .arg(example())
        .env("DISPLAY", &display)
        .env("SPNAV_SOCKET", &spnav)
        .env_remove("WAYLAND_DISPLAY")
        .env("RUST_LOG", "info")
        .stdout(Stdio::piped())
        .stderr(std::fs::File::create(shots.join("viewer.log")).expect("log file"))
        .spawn()
        .expect("cadre view starts");
    let stdout = child.stdout.take().expect("stdout");
    let (tx, lines) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut viewer = Viewer {
        _child: Killed(child),
        lines,
        display,
        window: String::new(),
        origin: (0, 0),
        seen: Default::default(),
    };
    let loaded = viewer.wait_for("loaded ");
    assert!(loaded.contains("2 instances"), "{loaded}");
    // Panels open with the model: the 3D view's area moves.
    // (The first area, before the panels, came before the model.)
    let area = viewer.wait_for("view area ");
    let numbers: Vec<u32> = area
        .trim_start_matches("view area ")
        .split_whitespace()
        .filter_map(|n| n.parse::<f64>().ok().map(|v| v as u32))
        .collect();
    viewer.origin = (numbers[0], numbers[1]);
    // The window, focused for the keyboard (there is no window manager to do it).
    let out = Command::new("xdotool")
        .args(["search", "--sync", "--name", "pin-assembly"])
        .env("DISPLAY", &viewer.display)
        .output()
        .expect("xdotool search");
    viewer.window = String::from_utf8_lossy(&out.stdout)
        .lines()
        .next()
        .expect("the viewer's window")
        .to_string();
    viewer.xdotool(&["windowfocus", "--sync", &viewer.window]);

    // A preset key: the front view, as `cadre render --view front` draws it.
    viewer.preset("1", "Front");
    let front = viewer.screenshot();
    let (vw, vh) = front.dimensions();
    assert!(vw > W / 3 && vh > H / 2, "the 3D view is {vw} × {vh}");
    let expected = expected_front(vw, vh);
    let diff = compare(&front, &expected, 24);
    assert!(
        diff.passes(0.02),
        "the front view differs from the offscreen render: {diff:?}"
    );

    // Orbit: a drag turns the view, the model stays in sight.
    viewer.mouse(vw / 2, vh / 2);
    // Paced like a hand: the viewer must see the press, the moves and the release in
    // different frames (a slow software GPU draws few of them).
    viewer.xdotool(&["mousedown", "1"]);
    std::thread::sleep(Duration::from_millis(300));
    for k in 1..=10 {
        viewer.mouse(vw / 2 + 8 * k, vh / 2 + 3 * k);
        std::thread::sleep(Duration::from_millis(80));
    }
    std::thread::sleep(Duration::from_millis(300));
    viewer.xdotool(&["mouseup", "1"]);
    let orbited = viewer.screenshot();
    assert!(
        differing(&front, &orbited) > 0.01,
        "the drag did not turn the view"
    );
    assert!(
        coverage(&orbited) > coverage(&front) / 3,
        "the model left the view"
    );

    // Zoom: the wheel brings the model closer.
    viewer.preset("1", "Front");
    let before = coverage(&viewer.screenshot());
    viewer.mouse(vw / 2, vh / 2);
    for _ in 0..5 {
        viewer.xdotool(&["click", "4"]);
        std::thread::sleep(Duration::from_millis(100));
    }
    let zoomed = coverage(&viewer.screenshot());
    assert!(
        zoomed as f64 > before as f64 * 1.3,
        "zoom: {before} → {zoomed} pixels"
    );

    // Click on the model: a face is selected and drawn orange.
    viewer.preset("1", "Front");
    let plain = viewer.screenshot();
    let (x, y) = model_pixel(&plain);
    viewer.mouse(x, y);
    viewer.xdotool(&["click", "1"]);
    let selected = viewer.wait_for("selected ");
    assert!(selected.contains("Face"), "{selected}");
    let tinted = viewer.screenshot();
    let (p, q) = (plain.get_pixel(x, y).0, tinted.get_pixel(x, y).0);
    assert!(
        q[1] > p[1] + 20,
        "the selected face is not tinted orange: {p:?} → {q:?}"
    );
    // Radius measurement on the same (cylindrical or planar) face: a result or a reason.
    viewer.key("r");
    viewer.mouse(x, y);
    viewer.xdotool(&["click", "1"]);
    viewer.wait_for("selected ");

    // Shift + F12: a screenshot larger than the window (the dialog's 3840 × 2160).
    viewer.key("shift+F12");
    let line = viewer.wait_for("screenshot ");
    let big = image::open(line.trim_start_matches("screenshot ").trim()).expect("4K screenshot");
    assert_eq!((big.width(), big.height()), (3840, 2160));
    assert!(
        coverage(&big.to_rgba8()) > 3840 * 2160 / 50,
        "the 4K screenshot shows the model"
    );

    // A section across the middle (key S) cuts the pins open: their caps show.
    viewer.key("Escape");
    viewer.preset("0", "Iso");
    let whole = viewer.screenshot();
    viewer.key("s");
    let cut = viewer.screenshot();
    assert!(
        differing(&whole, &cut) > 0.005,
        "the section changed nothing"
    );
    viewer.key("s");

    // The 3D mouse: a twist turns the view; button 1 goes to the iso view.
    viewer.saw_or_wait("spacemouse ");
    let still = viewer.screenshot();
    for _ in 0..20 {
        daemon.send_motion([0, 0, 0], [0, 300, 0], 16);
        std::thread::sleep(Duration::from_millis(16));
    }
    std::thread::sleep(Duration::from_millis(300));
    let twisted = viewer.screenshot();
    assert!(
        differing(&still, &twisted) > 0.01,
        "the 3D mouse did not turn the view"
    );
    daemon.send_button(1, true);
    viewer.wait_for("spacemouse button 1");
}

/// A pixel of the model in `image` (a non-background pixel near the middle of the model).
fn model_pixel(image: &RgbaImage) -> (u32, u32) {
    let covered: Vec<(u32, u32)> = image
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0[..3].iter().any(|&c| c < 200))
        .map(|(x, y, _)| (x, y))
        .collect();
    assert!(!covered.is_empty(), "no model in the image");
    // The covered pixel nearest the mean of the covered pixels of the largest blob is
    // enough here: the pins are solid discs or rectangles.
    let n = covered.len() as f64;
    let (mx, my) = covered.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + f64::from(x) / n, b + f64::from(y) / n)
    });
    *covered
        .iter()
        .min_by(|a, b| {
            let d = |p: &(u32, u32)| (f64::from(p.0) - mx).hypot(f64::from(p.1) - my);
            d(a).total_cmp(&d(b))
        })
        .expect("a pixel")
}

/// The front view of the example rendered offscreen as the viewer's screenshot does.
fn expected_front(width: u32, height: u32) -> RgbaImage {
    let doc = cadre_viewer::document::Document::load(&example(), &|_| {}).expect("example loads");
    let (lo, hi) = doc.bounds.expect("geometry");
    let camera = Camera::fit(
        lo,
        hi,
        ViewPreset::Front,
        false,
        f64::from(width) / f64::from(height),
    );
    let gpu = Gpu::headless().expect("a GPU or lavapipe");
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let prepared = renderer.prepare(&gpu, &doc.scene);
    renderer
        .render(
            &gpu,
            &prepared,
            &camera,
            &FrameOptions {
                width,
                height,
                supersample: 2,
                mode: DisplayMode::ShadedEdges,
                ..FrameOptions::default()
            },
            &cadre_render::ViewState::default(),
        )
        .expect("render")
}

/// A fresh folder for this run's screenshots and socket.
fn tempdir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cadre-view-e2e-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}
