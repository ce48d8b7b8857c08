//! The fitter against recordings made here: a shot simulated from known inputs, sampled
//! like the real recordings with a little noise, must be fitted back to those inputs.

use breakshot_shared::physics::{simulate, BallState, Models, Shot, Strike, TableKind};
use glam::DVec2;

use super::recording::{from_scene, parse, Units};
use super::{fit, start_params, Options};

/// Deterministic noise in [-1, 1] (a linear congruential generator).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A recording (JSON, metres) of `strike` on the first of `balls`, `delay` seconds after
/// the recording starts, every ball sampled every 20 ms with up to `noise` metres of error
/// on each coordinate.
fn record(id: u32, balls: &[DVec2], strike: Strike, delay: f64, noise: f64) -> String {
    let mut shot = Shot::new(
        TableKind::Carom,
        balls.iter().map(|&p| BallState::at_rest(p)).collect(),
    )
    .struck(0, strike);
    shot.params = start_params();
    shot.horizon = Some(6.0);
    let outcome = simulate(&shot).expect("the synthetic shot simulates");
    let mut rng = Noise(u64::from(id) + 1);
    let tracks: Vec<String> = (0..balls.len())
        .map(|i| {
            let (mut t, mut x, mut y) = (Vec::new(), Vec::new(), Vec::new());
            let mut k = 0;
            while f64::from(k) * 0.02 <= outcome.duration + delay {
                let time = f64::from(k) * 0.02;
                let p = outcome.state_at(i, time - delay).pos;
                let (rx, ry) = from_scene(p, 1.0);
                t.push(time);
                x.push(rx + noise * rng.next());
                y.push(ry + noise * rng.next());
                k += 1;
            }
            format!(r#""{}": {{"t": {t:?}, "x": {x:?}, "y": {y:?}}}"#, i + 1)
        })
        .collect();
    format!(r#"{{"id": {id}, "balls": {{{}}}}}"#, tracks.join(", "))
}

#[test]
fn a_simulated_shot_is_fitted_back_to_its_strike() {
    let balls = [
        DVec2::new(0.4, 0.6),
        DVec2::new(1.0, 1.9),
        DVec2::new(0.3, 2.2),
    ];
    let truth = Strike::at_angle(2.5, 63.0, DVec2::new(0.25, 0.15));
    let text = format!("[{}]", record(1, &balls, truth, 0.012, 0.002));
    let recordings = parse(&text, Units::Metres).expect("parses");
    assert_eq!(recordings[0].cue, 0, "the struck ball moves first");
    let options = Options {
        units: Units::Metres,
        fit_cloth: false,
        ..Options::default()
    };
    let fit = fit(recordings, options, false).expect("fits");
    let got = fit.fitted_fits[0];
    assert!(got.rmse < 0.01, "RMSE {} m", got.rmse);
    assert!((got.angle_deg - 63.0).abs() < 0.5, "aim {}", got.angle_deg);
    assert!((got.speed - 2.5).abs() < 0.1, "speed {}", got.speed);
    let tip = DVec2::from_array(got.tip);
    assert!((tip - truth.tip).length() < 0.1, "tip {tip}");
    assert!(
        (got.delay - 0.012).abs() < 0.003,
        "strike at {} s",
        got.delay
    );
    // Fitting under the same parameters as the recording, the start and fitted fits agree.
    assert_eq!(fit.start, fit.fitted);
}

#[test]
fn recorded_start_positions_are_made_valid() {
    // Two balls recorded on one spot are nudged apart, a ball off the bed is moved inside
    // the cushions: the recording's rounding must not stop the fit.
    let text = r#"[{"id": 3, "balls": {
        "1": {"t": [0, 0.02, 0.04], "x": [0, 0.01, 0.02], "y": [0, 0, 0]},
        "2": {"t": [0, 1], "x": [0, 0], "y": [0, 0]},
        "3": {"t": [0, 1], "x": [5, 5], "y": [0, 0]}}}]"#;
    let recordings = parse(text, Units::Metres).expect("parses");
    let shot = super::strike::base_shot(&recordings[0], &start_params(), Models::default());
    assert!(shot.is_ok(), "{shot:?}");
}
