//! The fuzz targets as plain functions, so that `cargo fuzz` (through the files in
//! `fuzz_targets/`) and the stable `replay-corpus` runner call exactly the same code. Each
//! takes any bytes; it must never panic, and where the input is accepted the results must
//! keep the engine's invariants.

use breakshot_shared::physics::{
    simulate, BallState, MotionState, Params, Shot, Strike, TableKind,
};
use breakshot_shared::protocol::{
    command_of, decode_payload, split_frame, validate, ClientMessage, ServerMessage,
};
use breakshot_shared::replay::GameRecord;
use breakshot_shared::rules::{EightBallRules, Game, Settings, Variant};
use breakshot_shared::scene::Scene;
use glam::DVec2;

/// Balls may touch after a shot, never overlap by more than this (metres).
const OVERLAP_TOLERANCE: f64 = 1e-9;

/// The frame decoder and message parsing: split a frame off the bytes, decode it as either
/// side's message, and run the server's checks on a client message.
pub fn frame(data: &[u8]) {
    for payload in [split_frame(data).ok().flatten().map(|(p, _)| p), Some(data)]
        .into_iter()
        .flatten()
    {
        if let Ok(msg) = decode_payload::<ClientMessage>(payload) {
            if let Ok(valid) = validate(msg) {
                let _ = command_of(&valid, None);
            }
        }
        let _ = decode_payload::<ServerMessage>(payload);
    }
}

/// The scene parser, then the scene's simulation when it parses.
pub fn scene(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(scene) = Scene::from_json(text) {
        let _ = scene.run(None);
    }
}

/// Game-record decoding, then a replay of what decodes.
pub fn record(data: &[u8]) {
    if let Ok(record) = GameRecord::decode(data) {
        let _ = record.replay();
    }
}

/// Any bytes as a shot: a table with balls placed from the bytes and a strike whose numbers
/// are raw bits from the bytes (NaN, infinities and all). The strike must be refused by the
/// cue's checks or the shot by the engine's, or else simulate with every invariant holding.
/// The same bytes are also tried as a client command on a real game.
pub fn shot(data: &[u8]) {
    let mut bytes = Bytes(data);
    let table = [
        TableKind::Open,
        TableKind::SevenFoot,
        TableKind::EightFoot,
        TableKind::NineFoot,
    ][usize::from(bytes.byte() % 4)];
    // An open table has no edges: place its balls in a nine-foot table's area.
    let (width, length) = table
        .size()
        .or(TableKind::NineFoot.size())
        .unwrap_or((1.27, 2.54));
    let count = 1 + usize::from(bytes.byte() % 16);
    let balls: Vec<BallState> = (0..count)
        .map(|_| BallState::at_rest(DVec2::new(bytes.unit() * width, bytes.unit() * length)))
        .collect();
    let strike = Strike {
        speed: bytes.f64(),
        dir: DVec2::new(bytes.f64(), bytes.f64()),
        tip: DVec2::new(bytes.f64(), bytes.f64()),
        // Elevated strikes too: jumps, massé and balls leaving the table.
        elevation_deg: bytes.unit() * 90.0,
    };
    if let Ok(strike) = strike.validated() {
        let shot = Shot::new(table, balls).struck(0, strike);
        if let Ok(outcome) = simulate(&shot) {
            check_table(&outcome.finals, Params::default().ball_radius);
        }
    }
    // The rest of the bytes as a client command on a freshly racked game.
    let seed = u64::from_le_bytes(bytes.array());
    let mut game = Game::new(
        Variant::EightBall(EightBallRules::Wpa),
        Settings::offline(),
        seed,
    );
    let Ok(msg) = decode_payload::<ClientMessage>(bytes.rest()) else {
        return;
    };
    let Ok(msg) = validate(msg) else {
        return;
    };
    if let Some((_, command)) = command_of(&msg, None) {
        let seat = game.to_move();
        if game.apply(seat, &command).is_ok() {
            check_table(game.balls(), Params::default().ball_radius);
        }
    }
}

/// Finite states and no two balls on the table overlapping.
fn check_table(balls: &[BallState], radius: f64) {
    let on_table: Vec<&BallState> = balls
        .iter()
        .filter(|b| b.motion != MotionState::Pocketed)
        .collect();
    for b in &on_table {
        assert!(
            b.pos.is_finite() && b.vel.is_finite() && b.spin.is_finite(),
            "a ball's state is not finite: {b:?}"
        );
    }
    for (i, a) in on_table.iter().enumerate() {
        for b in &on_table[i + 1..] {
            let overlap = 2.0 * radius - a.pos.distance(b.pos);
            assert!(
                overlap <= OVERLAP_TOLERANCE,
                "balls overlap by {overlap} m: {a:?} {b:?}"
            );
        }
    }
}

/// Reads numbers off the front of the input, with zeros once it runs out.
struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        let n = N.min(self.0.len());
        out[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        out
    }

    fn byte(&mut self) -> u8 {
        self.array::<1>()[0]
    }

    /// A number in 0..=1.
    fn unit(&mut self) -> f64 {
        f64::from(u16::from_le_bytes(self.array())) / f64::from(u16::MAX)
    }

    fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.array())
    }

    fn rest(&mut self) -> &'a [u8] {
        std::mem::take(&mut self.0)
    }
}
