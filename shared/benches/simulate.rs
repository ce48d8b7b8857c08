//! Simulation time of typical shots: one ball, a draw shot, the 8-ball break of the reference
//! comparison, a 9-ball break, a frozen cradle and a snooker break-off (22 balls). The scenes
//! are the files in `examples/`.
//!
//! `cargo bench -p breakshot-shared --bench simulate`

use std::hint::black_box;
use std::path::Path;

use breakshot_shared::physics::{Shot, Simulator};
use breakshot_shared::scene::Scene;
use criterion::{criterion_group, criterion_main, Criterion};

/// The shot of `examples/NAME`; a missing or broken example is a broken build of the
/// benchmark, so it stops with the reason.
fn example(name: &str) -> Shot {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    Scene::from_json(&text)
        .and_then(|scene| scene.to_shot())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn simulate(c: &mut Criterion) {
    let scenes = [
        ("one_ball", "one_ball.json"),
        ("draw_shot", "draw_shot.json"),
        ("break_8ball_7ft", "break_8ball_7ft.json"),
        ("break_9ball_9ft", "break_9ft.json"),
        ("frozen_cradle", "frozen_cradle.json"),
        ("break_snooker_22", "snooker_break.json"),
    ];
    let mut group = c.benchmark_group("simulate");
    for (name, file) in scenes {
        let shot = example(file);
        let mut sim = Simulator::new();
        group.bench_function(name, |b| {
            b.iter(|| sim.run(black_box(&shot)).map(|o| o.events.len()))
        });
    }
    group.finish();
}

criterion_group!(benches, simulate);
criterion_main!(benches);
