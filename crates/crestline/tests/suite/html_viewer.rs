//! End to end: the HTML viewer opened in headless Chromium draws the mesh, and its toggles
//! (set through the URL hash) change the picture.
//!
//! Needs a Chromium binary (`chromium`, `chromium-browser`, `google-chrome` or
//! `google-chrome-stable` in PATH, or the path in `CRESTLINE_CHROMIUM`). Without one the test
//! prints a loud SKIPPED message on stderr and returns.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test helpers may fail loudly

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crestline::lines::{FeatureLines, LineKind};
use crestline::render::{RenderOptions, UpAxis, write_html};
use crestline::shapes;

use crate::common::circle;

const CANDIDATES: [&str; 4] = [
    "chromium",
    "chromium-browser",
    "google-chrome",
    "google-chrome-stable",
];

fn find_chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("CRESTLINE_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| CANDIDATES.iter().map(move |name| dir.join(name)))
        .find(|p| p.is_file())
}

/// A fresh directory under the system's temporary folder.
fn fresh_dir(tag: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!("crestline-{tag}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Opens `html#hash` in headless Chromium and returns the screenshot's RGBA pixels.
fn screenshot(chromium: &Path, html: &Path, hash: &str, work: &Path) -> tiny_skia::Pixmap {
    let name = hash.replace(['=', '&'], "_");
    let shot = work.join(format!("shot-{name}.png"));
    let profile = fresh_dir("chromium-profile");
    let url = format!("file://{}#{hash}", html.display());
    let mut child = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--window-size=640,480",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", chromium.display()));
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            assert!(status.success(), "chromium exited with {status} on {url}");
            break;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within 120 s on {url}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let _ = std::fs::remove_dir_all(&profile);
    tiny_skia::Pixmap::load_png(&shot)
        .unwrap_or_else(|e| panic!("no screenshot {} of {url}: {e}", shot.display()))
}

/// Pixels within `tolerance` (per channel) of `color`, below the control panel.
fn count_near(img: &tiny_skia::Pixmap, color: [u8; 3], tolerance: i32) -> usize {
    let w = img.width() as usize;
    img.pixels()
        .iter()
        .enumerate()
        .filter(|(i, _)| i / w > 120)
        .filter(|(_, p)| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()]
                .iter()
                .zip(color)
                .all(|(&a, b)| (i32::from(a) - i32::from(b)).abs() <= tolerance)
        })
        .count()
}

/// Pixels that differ from the page background (white) below the control panel.
fn count_not_white(img: &tiny_skia::Pixmap) -> usize {
    let w = img.width() as usize;
    img.pixels()
        .iter()
        .enumerate()
        .filter(|(i, p)| i / w > 120 && (p.red() < 250 || p.green() < 250 || p.blue() < 250))
        .count()
}

#[test]
fn viewer_draws_in_chromium_and_toggles_change_the_picture() {
    let Some(chromium) = find_chromium() else {
        let message = format!(
            "\n*** SKIPPED viewer_draws_in_chromium_and_toggles_change_the_picture: no Chromium \
             binary found (looked for {} in PATH and CRESTLINE_CHROMIUM). Install it with \
             `apt-get install -y chromium` to run this test. ***\n",
            CANDIDATES.join(", ")
        );
        eprintln!("{message}");
        // The test harness captures eprintln! of passing tests; writing to the stderr handle
        // itself is not captured, so the skip shows in a plain `cargo test` run.
        let _ = std::io::Write::write_all(&mut std::io::stderr(), message.as_bytes());
        return;
    };
    let work = fresh_dir("html-viewer");
    let mesh = shapes::torus(3.0, 1.0, 96, 48);
    let lines = FeatureLines {
        lines: vec![
            circle(LineKind::Ridge, 4.0, 0.0, 120),
            circle(LineKind::Ridge, 3.0, 1.0, 120),
            circle(LineKind::Valley, 2.0, 0.0, 120),
        ],
    };
    let field: Vec<f64> = mesh.positions().iter().map(|p| p.z).collect();
    let mut opts = RenderOptions::default()
        .with_up(UpAxis::Z)
        .with_view(20.0, 40.0);
    opts.line_width = 4.0;
    opts.line_halo = None;
    let html = work.join("view.html");
    write_html(&html, &mesh, Some(&lines), Some(&field), &opts).unwrap();

    let all = screenshot(&chromium, &html, "ridges=1&valleys=1&field=0", &work);
    let bare = screenshot(&chromium, &html, "ridges=0&valleys=0&field=0", &work);
    let colored = screenshot(&chromium, &html, "ridges=0&valleys=0&field=1", &work);

    let total = (all.width() * all.height()) as usize;
    let drawn = count_not_white(&bare);
    assert!(
        drawn > total / 20,
        "the mesh covers only {drawn} of {total} pixels: is WebGL working?"
    );
    let red = |img| count_near(img, opts.ridge_color, 40);
    let blue = |img| count_near(img, opts.valley_color, 40);
    assert!(red(&all) > 200, "ridges on: {} red pixels", red(&all));
    assert!(blue(&all) > 100, "valleys on: {} blue pixels", blue(&all));
    assert!(red(&bare) < 20, "ridges off: {} red pixels", red(&bare));
    assert!(blue(&bare) < 20, "valleys off: {} blue pixels", blue(&bare));
    // Viridis: the bottom of the torus is dark purple, the top yellow-green; grey has
    // equal channels.
    let colorful = |img: &tiny_skia::Pixmap| {
        img.pixels()
            .iter()
            .filter(|p| {
                let c = [p.red(), p.green(), p.blue()].map(i32::from);
                c.iter().max().unwrap() - c.iter().min().unwrap() > 60
            })
            .count()
    };
    assert!(
        colorful(&colored) > total / 20 && colorful(&bare) < total / 100,
        "colour map on: {} coloured pixels, off: {}",
        colorful(&colored),
        colorful(&bare)
    );
    let _ = std::fs::remove_dir_all(&work);
}
