//! The store's write cost per command as a game grows: one durable transaction per command
//! (as the writer thread commits when games are not sharing a flush), appending one command
//! row. Beside it, the size of the whole record, which is what each command rewrote before
//! games were stored as a log.
//!
//! `cargo bench -p breakshot-server --bench store` prints the median time of a commit at
//! several game lengths, in a scratch directory under the system's temporary directory (on
//! the same disk as a real store only if that is where it lives: set TMPDIR).

use std::time::{Duration, Instant};

use breakshot_server::output::{RoomMeta, StoreOp};
use breakshot_server::store::Store;
use breakshot_shared::physics::Strike;
use breakshot_shared::protocol::{AimAid, RoomCode};
use breakshot_shared::replay::{GameRecord, RecordEntry};
use breakshot_shared::rules::{Command, Seat, Settings, Variant};
use glam::DVec2;

/// Game lengths at which commits are timed, and commits timed at each.
const LENGTHS: [usize; 4] = [10, 100, 500, 1_000];
const SAMPLES: usize = 30;

fn entry(i: usize) -> RecordEntry {
    RecordEntry {
        seat: if i % 2 == 0 { Seat::A } else { Seat::B },
        command: Command::Shot {
            strike: Strike {
                speed: 5.0 + i as f64 * 1e-3,
                dir: DVec2::new(0.3, 0.9),
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            },
            call: None,
        },
        hash: Some(0x9e37_79b9_7f4a_7c15 ^ i as u64),
        chain: i as u64,
    }
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn main() {
    let scratch = breakshot_testkit::scratch("store-bench");
    let dir = scratch.path();
    let mut store = Store::open(dir).expect("store");
    let code = RoomCode::parse("BENCH234").expect("room code");
    let mut record = GameRecord::new(
        Variant::EightBall(Default::default()),
        Settings::offline(),
        1,
    );
    let mut ops = vec![StoreOp::Room(RoomMeta {
        code: code.clone(),
        variant: record.variant,
        settings: record.settings,
        aim_aid: AimAid::Off,
        seats: [None, None],
    })];
    ops.extend(StoreOp::whole_game(&code, 1, &record));
    store.apply(&ops.iter().collect::<Vec<_>>()).expect("start");

    println!("game length | append one row | row size | whole record (rewritten before)");
    let mut length = 0;
    for target in LENGTHS {
        // Grow the game to just before `target`, then time SAMPLES commits of each kind.
        while length + SAMPLES < target {
            append(&mut store, &code, &mut record, length);
            length += 1;
        }
        let mut appends = Vec::new();
        for _ in 0..SAMPLES {
            let t = Instant::now();
            append(&mut store, &code, &mut record, length);
            appends.push(t.elapsed());
            length += 1;
        }
        let bytes = record.encode();
        println!(
            "{length:>11} | {:>14.2?} | {:>5} bytes | {} bytes",
            median(appends),
            entry(length).encode().len(),
            bytes.len()
        );
    }
}

fn append(store: &mut Store, code: &RoomCode, record: &mut GameRecord, index: usize) {
    let e = entry(index);
    let op = StoreOp::Command {
        room: code.clone(),
        number: 1,
        index: u32::try_from(index).expect("index"),
        entry: e.encode(),
    };
    store.apply(&[&op]).expect("append");
    record.entries.push(e);
}
