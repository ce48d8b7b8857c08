//! The fitter against recordings made here: a shot simulated from known inputs, sampled
//! like the real recordings with a little noise, must be fitted back to those inputs.

use breakshot_shared::physics::{simulate, BallState, Models, Params, Shot, Strike, TableKind};
use glam::DVec2;

use super::cli::{start_params, Error};
use super::recording::{from_scene, parse, Units};
use super::{fit, pool_start, Options, Start};

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

/// A recording (JSON, metres) of `strike` on the first of `balls` under `params`, `delay`
/// seconds after the recording starts, every ball sampled every 20 ms with up to `noise`
/// metres of error on each coordinate.
fn record(
    id: u32,
    params: Params,
    balls: &[DVec2],
    strike: Strike,
    delay: f64,
    noise: f64,
) -> String {
    let mut shot = Shot::new(
        TableKind::Carom,
        balls.iter().map(|&p| BallState::at_rest(p)).collect(),
    )
    .struck(0, strike);
    shot.params = params;
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
    let text = format!("[{}]", record(1, pool_start(), &balls, truth, 0.012, 0.002));
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
    let shot = super::strike::base_shot(&recordings[0], &pool_start(), Models::default());
    assert!(shot.is_ok(), "{shot:?}");
}

#[test]
fn start_names_the_parameters_the_fit_starts_from() {
    let named = |arg: &str| match start_params(arg) {
        Ok(p) => p,
        Err(_) => panic!("--start {arg} refused"),
    };
    assert_eq!(named("pool"), (Start::Pool, pool_start()));
    let carom = Params::for_table(TableKind::Carom);
    assert_eq!(named("defaults"), (Start::Defaults, carom));
    assert_ne!(carom, pool_start());
    // A file holds a scene's `physics` object, over the carom table's defaults.
    let dir = breakshot_testkit::scratch("fit-start");
    let file = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("written");
        path.to_string_lossy().into_owned()
    };
    let good = file("good.json", r#"{"mu_roll": 0.006, "e_cushion": 0.9}"#);
    let expected = Params {
        mu_roll: 0.006,
        e_cushion: 0.9,
        ..carom
    };
    assert_eq!(named(&good), (Start::File, expected));
    // Bad values are refused with a message that names them.
    let missing = dir
        .path()
        .join("missing.json")
        .to_string_lossy()
        .into_owned();
    for (arg, says) in [
        ("nonsense".to_string(), "not pool, defaults"),
        (missing, "not pool, defaults"),
        (file("text.json", "mu_roll = 1"), "not JSON"),
        (file("list.json", "[0.2, 0.01]"), "JSON object"),
        (file("typo.json", r#"{"mu_rol": 0.01}"#), "mu_rol"),
        (file("type.json", r#"{"mu_roll": "fast"}"#), "physics"),
        (file("range.json", r#"{"mu_slide": -0.2}"#), "mu_slide"),
        (file("above.json", r#"{"e_cushion": 1.5}"#), "e_cushion"),
    ] {
        match start_params(&arg) {
            Err(Error::Invalid(msg)) => {
                assert!(
                    msg.starts_with("--start ") && msg.contains(says),
                    "{arg}: {msg}"
                );
            }
            Err(Error::Other(e)) => panic!("{arg}: not a usage error: {e}"),
            Ok(p) => panic!("{arg} accepted: {p:?}"),
        }
    }
}

#[test]
fn strikes_are_fitted_under_the_start_parameters() {
    // A long shot recorded on the carom cloth: under its own parameters (`--start defaults`)
    // the strike fits back closely; under the pool cloth, whose rolling resistance is twice
    // as high, no strike matches its slowing down as well.
    let carom = Params::for_table(TableKind::Carom);
    let balls = [
        DVec2::new(0.4, 0.4),
        DVec2::new(1.1, 2.5),
        DVec2::new(0.2, 2.6),
    ];
    let truth = Strike::at_angle(1.6, 75.0, DVec2::new(0.0, 0.2));
    let text = format!("[{}]", record(2, carom, &balls, truth, 0.01, 0.001));
    let fit_from = |start_from: Start, start: Params| {
        let recordings = parse(&text, Units::Metres).expect("parses");
        let options = Options {
            units: Units::Metres,
            fit_cloth: false,
            start_from,
            start,
            iters: 40,
            ..Options::default()
        };
        fit(recordings, options, false).expect("fits")
    };
    let own = fit_from(Start::Defaults, carom);
    assert_eq!(own.start, carom);
    assert_eq!(own.fitted, carom, "strikes only: the parameters are kept");
    let pool = fit_from(Start::Pool, pool_start());
    let (own, pool) = (own.fitted_fits[0].rmse, pool.fitted_fits[0].rmse);
    assert!(own < 0.01, "own cloth: RMSE {own} m");
    assert!(pool > 2.0 * own, "pool cloth: RMSE {pool} m, own {own} m");
}

#[test]
fn cross_validation_scores_each_shot_under_parameters_fitted_without_it() {
    let carom = Params::for_table(TableKind::Carom);
    let shots = [
        ([0.4, 0.4], [1.1, 2.5], [0.2, 2.6], 70.0),
        ([0.7, 2.4], [0.3, 0.9], [1.1, 0.5], 250.0),
    ];
    let records: Vec<String> = shots
        .iter()
        .enumerate()
        .map(|(k, (a, b, c, aim))| {
            let balls = [a, b, c].map(|p| DVec2::from_array(*p));
            let strike = Strike::at_angle(1.4, *aim, DVec2::new(0.1, 0.1));
            record(10 + k as u32, carom, &balls, strike, 0.01, 0.001)
        })
        .collect();
    let recordings = parse(&format!("[{}]", records.join(", ")), Units::Metres).expect("parses");
    let options = Options {
        units: Units::Metres,
        iters: 8,
        rounds: 1,
        ..Options::default()
    };
    let cv = super::crossval::run(recordings.clone(), options, 2, false).expect("runs");
    assert_eq!(cv.fold_of, vec![0, 1]);
    for (i, rec) in recordings.iter().enumerate() {
        let fold = &cv.folds[cv.fold_of[i]];
        assert_eq!(fold.seen.len(), 1, "fitted on the other shot");
        assert_ne!(
            fold.fitted, options.start,
            "the shared parameters were fitted"
        );
        // The held-out figure is the shot's strike found under the start parameters, then
        // searched again under that fold's parameters once a round, as the fitted shots are.
        let mut searched = fit(
            vec![rec.clone()],
            Options {
                fit_cloth: false,
                ..options
            },
            false,
        )
        .expect("fits")
        .start_fits;
        for _ in 0..options.rounds {
            searched = super::refit_strikes(
                std::slice::from_ref(rec),
                &fold.fitted,
                &searched,
                &options,
                &indicatif::ProgressBar::hidden(),
            )
            .expect("refits");
        }
        assert_eq!(cv.held_out[i], searched[0], "shot {i}");
        // So it is never worse than a strikes-only fit under that fold's parameters.
        let alone = fit(
            vec![rec.clone()],
            Options {
                fit_cloth: false,
                start: fold.fitted,
                ..options
            },
            false,
        )
        .expect("fits");
        assert!(cv.held_out[i].rmse <= alone.fitted_fits[0].rmse, "shot {i}");
    }
    assert!(super::crossval::run(recordings, options, 3, false).is_err());
}
