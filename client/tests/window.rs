//! The window under a virtual display: `breakshot practice SCENE --screenshot` must draw the
//! cloth over the table and each ball, in its colour, where the layout puts it.
//!
//! Needs `xvfb-run`; without it the test says why and passes (CI installs it).

use std::path::{Path, PathBuf};
use std::process::Command;

use breakshot_client::view::layout::{Frame, Layout};
use breakshot_client::view::palette::{ball_look, Rgb, BALL_WHITE, CLOTH};
use breakshot_shared::scene::Scene;

const SCENE: &str = r#"{
  "table": "9ft",
  "balls": [
    {"id": "cue", "pos": [0.635, 0.9]},
    {"id": "1",   "pos": [0.30, 1.60]},
    {"id": "2",   "pos": [0.95, 1.40]},
    {"id": "3",   "pos": [0.20, 2.20]},
    {"id": "8",   "pos": [0.635, 1.90]},
    {"id": "11",  "pos": [1.05, 2.30]},
    {"id": "14",  "pos": [0.45, 2.05]}
  ]
}"#;

fn find_in_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).expect("screenshot written");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

fn close(a: Rgb, b: Rgb, tolerance: i32) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, y)| (x as i32 - y as i32).abs() <= tolerance)
}

#[test]
fn practice_screenshot_shows_cloth_and_balls_where_the_layout_puts_them() {
    let Some(xvfb) = find_in_path("xvfb-run") else {
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb)");
        return;
    };
    let dir = std::env::temp_dir().join(format!("breakshot-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let scene_path = dir.join("scene.json");
    let shot_path = dir.join("out.png");
    std::fs::write(&scene_path, SCENE).expect("scene written");

    let status = Command::new(xvfb)
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_breakshot"))
        .arg("practice")
        .arg(&scene_path)
        .arg("--screenshot")
        .arg(&shot_path)
        .args(["--frames", "4", "--size", "1280x720"])
        .status()
        .expect("xvfb-run runs");
    assert!(status.success(), "breakshot exited with {status}");

    let (w, h, pixels) = read_png(&shot_path);
    assert_eq!((w, h), (1280, 720));
    let at = |x: f32, y: f32| -> Rgb {
        let (x, y) = (x.round() as usize, y.round() as usize);
        let i = (y * w as usize + x) * 4;
        [pixels[i], pixels[i + 1], pixels[i + 2]]
    };

    let scene = Scene::from_json(SCENE).expect("valid scene");
    let shot = scene.to_shot().expect("valid shot");
    let layout = Layout::new(w as f32, h as f32, Frame::new(shot.table, &shot.balls));

    // The cloth colour fills most of the table (balls and aiming lines cover a little)...
    let c = layout.cloth;
    let (mut cloth, mut total) = (0, 0);
    for i in 1..40 {
        for j in 1..20 {
            let p = at(c.x + c.w * i as f32 / 40.0, c.y + c.h * j as f32 / 20.0);
            cloth += close(p, CLOTH, 6) as u32;
            total += 1;
        }
    }
    assert!(
        cloth * 100 > total * 90,
        "cloth colour at {cloth} of {total} points"
    );
    // ... and stops at the cushions.
    assert!(!close(at(c.x - layout.px(0.09), c.y + 0.3 * c.h), CLOTH, 6));

    // Each ball's colour left and right of its centre (clear of the number in the middle).
    let r = layout.px(shot.params.ball_radius);
    for (ball, state) in scene.balls.iter().zip(&shot.balls) {
        let [x, y] = layout.to_screen(state.pos);
        let look = ball_look(&ball.id);
        for dx in [-0.75 * r, 0.75 * r] {
            let got = at(x + dx, y);
            assert!(
                close(got, look.color, 8),
                "ball {} at ({x}, {y}): saw {got:?}, want {:?}",
                ball.id,
                look.color
            );
        }
        // A striped ball is white above and below its band.
        if look.stripe {
            let cap = at(x, y - 0.85 * r);
            assert!(close(cap, BALL_WHITE, 12), "ball {} top: {cap:?}", ball.id);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
