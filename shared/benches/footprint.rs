//! Memory footprint of a simulation: heap allocations in the event loop, and the size of a
//! break's full result.
//!
//! A counting global allocator counts every allocation. Each scene is simulated twice with
//! the same `Simulator`: the first run sizes its buffers; the second may allocate only a small
//! constant number of times (checking the shot builds a few short lists), never per event.
//! Then the break's events and trajectory pieces are encoded with bincode and JSON and
//! compared with the 64 KiB budget.
//!
//! `cargo bench -p breakshot-shared --bench footprint` prints the figures and exits with
//! status 1 if a second run allocated more than that constant or a result is over budget.

// A global allocator is `unsafe impl GlobalAlloc`; it only forwards to the system allocator.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};

use breakshot_shared::physics::{BallState, Event, Outcome, Shot, Simulator};
use breakshot_shared::scene::Scene;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static BYTES: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(new_size, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Most allocations a second run may make: a `Simulator` reuses every buffer, so none.
const MAX_ALLOCATIONS_PER_RUN: usize = 0;

/// The largest full result of a break the project accepts.
const RESULT_BUDGET: usize = 64 * 1024;

fn example(name: &str) -> Result<Shot, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name);
    let text =
        std::fs::read_to_string(&path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    Scene::from_json(&text)
        .and_then(|scene| scene.to_shot())
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Allocations (count, bytes) made by `f`.
fn count<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
    let (a0, b0) = (
        ALLOCATIONS.load(Ordering::Relaxed),
        BYTES.load(Ordering::Relaxed),
    );
    let out = f();
    let (a1, b1) = (
        ALLOCATIONS.load(Ordering::Relaxed),
        BYTES.load(Ordering::Relaxed),
    );
    (out, a1 - a0, b1 - b0)
}

/// What a full result holds: every event, and every piece of every ball's trajectory as its
/// start time and start state (the rest of a piece follows from those and the parameters).
fn full_result(outcome: &Outcome) -> (Vec<Event>, Vec<Vec<(f64, BallState)>>) {
    let history = outcome
        .history
        .iter()
        .map(|pieces| pieces.iter().map(|p| (p.t0, p.start)).collect())
        .collect();
    (outcome.events.clone(), history)
}

fn main() -> ExitCode {
    let mut ok = true;
    println!("scene                  events  allocs run 1  allocs run 2  bytes run 2");
    for name in [
        "break_8ball_7ft.json",
        "break_9ft.json",
        "frozen_cradle.json",
        "draw_shot.json",
        "jump_9ft.json",
    ] {
        let shot = match example(name) {
            Ok(shot) => shot,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::FAILURE;
            }
        };
        let mut sim = Simulator::new();
        let (first, allocs_1, _) = count(|| sim.run(&shot).map(|o| o.events.len()));
        let (_, allocs_2, bytes_2) = count(|| sim.run(&shot).map(|o| o.events.len()));
        let events = match first {
            Ok(n) => n,
            Err(e) => {
                eprintln!("{name}: {e}");
                return ExitCode::FAILURE;
            }
        };
        println!("{name:22} {events:6} {allocs_1:13} {allocs_2:13} {bytes_2:12}");
        if allocs_2 > MAX_ALLOCATIONS_PER_RUN {
            ok = false;
        }
    }
    println!();
    for name in ["break_8ball_7ft.json", "break_9ft.json"] {
        let Ok(shot) = example(name) else {
            return ExitCode::FAILURE;
        };
        let outcome = match Simulator::new().run(&shot) {
            Ok(o) => o.clone(),
            Err(e) => {
                eprintln!("{name}: {e}");
                return ExitCode::FAILURE;
            }
        };
        let result = full_result(&outcome);
        let pieces: usize = result.1.iter().map(Vec::len).sum();
        let binary = bincode::serde::encode_to_vec(&result, bincode::config::standard())
            .map(|v| v.len())
            .unwrap_or(usize::MAX);
        let json = serde_json::to_vec(&result)
            .map(|v| v.len())
            .unwrap_or(usize::MAX);
        println!(
            "{name}: {} events, {pieces} pieces: bincode {binary} B ({:.1} KiB), JSON {json} B ({:.1} KiB); budget {} KiB",
            result.0.len(),
            binary as f64 / 1024.0,
            json as f64 / 1024.0,
            RESULT_BUDGET / 1024
        );
        if binary > RESULT_BUDGET {
            ok = false;
        }
    }
    if ok {
        println!(
            "\nat most {MAX_ALLOCATIONS_PER_RUN} allocations in a second run, none per event; \
             results within budget"
        );
        ExitCode::SUCCESS
    } else {
        println!(
            "\nFAILED: a second run allocated more than {MAX_ALLOCATIONS_PER_RUN} times, or a \
             result is over budget"
        );
        ExitCode::FAILURE
    }
}
