//! The accuracy/cost study: what the event-based engine's exactness costs, against
//! fixed-step integration at several steps, on one workload; and what each effect costs.
//!
//! `run_study` does the work and returns plain data; `report` and `plot` turn it into the
//! published files.

pub mod effects;
pub mod fixed_step;
pub mod methods;
pub mod metrics;
pub mod plot;
pub mod report;
pub mod trace;
pub mod workload;

use std::path::Path;

use anyhow::Context;
use breakshot_shared::physics::{Shot, Simulator};
use indicatif::{ProgressBar, ProgressStyle};

use effects::{DisabledCheck, EffectCosts};
use methods::{Method, Timed};
use metrics::{compare, first_collision, saw_collision, Comparison};
use workload::{Case, Category};

/// One method on one shot, compared with the reference.
#[derive(Clone, Debug)]
pub struct Row {
    pub case: usize,
    pub method: usize,
    pub seconds: f64,
    pub steps: u64,
    pub deepest_overlap: f64,
    /// Balls that tunnelled out of the table.
    pub escaped: usize,
    pub comparison: Comparison,
    /// The first ball–ball collision is the reference's.
    pub first_collision_matches: bool,
    /// The cue ball met ball 1 if and only if it did in the reference.
    pub object_contact_matches: bool,
}

/// Everything the study measured.
pub struct Study {
    pub cases: Vec<Case>,
    pub methods: Vec<Method>,
    pub rows: Vec<Row>,
    pub effects: EffectCosts,
    /// Shots left out because the reference engine could not simulate them, with why.
    pub skipped: Vec<(Case, String)>,
    pub disabled: DisabledCheck,
}

/// Runs the whole study, showing progress.
pub fn run_study() -> anyhow::Result<Study> {
    let all_cases = workload::workload();
    let methods = Method::all();
    let ladder_len = effects::ladder().len();
    let breaks = all_cases.iter().filter(|c| c.category.is_break()).count();
    let total = all_cases.len() * methods.len() + ladder_len * breaks + 1;
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:24} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        )
        .context("progress bar template")?,
    );
    let mut sim = Simulator::new();
    let mut rows = Vec::new();
    let mut cases = Vec::new();
    let mut skipped = Vec::new();
    for case in all_cases {
        bar.set_message(case.name.split(':').next().unwrap_or("").to_string());
        let reference = match methods::run(Method::Event, &case.shot, &mut sim) {
            Ok(r) => r,
            Err(e) => {
                skipped.push((case, format!("{e:#}")));
                bar.inc(methods.len() as u64);
                continue;
            }
        };
        let ci = cases.len();
        for (mi, &method) in methods.iter().enumerate() {
            let timed = if method == Method::Event {
                reference.clone()
            } else {
                methods::run(method, &case.shot, &mut sim)
                    .with_context(|| format!("shot {} with {}", case.name, method.label()))?
            };
            rows.push(row(ci, mi, &reference, &timed));
            bar.inc(1);
        }
        cases.push(case);
    }
    bar.set_message("cost of each effect");
    let effect_shots: Vec<(String, Shot)> = cases
        .iter()
        .filter(|c| c.category.is_break())
        .map(|c| (c.name.clone(), c.shot.clone()))
        .collect();
    bar.inc((ladder_len * (breaks - effect_shots.len())) as u64);
    let effects = effects::cost_of_effects(&effect_shots, || bar.inc(1));
    bar.set_message("disabled effects");
    let nine_ball = workload::break_case(Category::Break9, 0);
    let disabled = effects::disabled_effects_cost_nothing(&nine_ball.shot)?;
    bar.inc(1);
    bar.finish_with_message("done");
    Ok(Study {
        cases,
        methods,
        rows,
        effects,
        disabled,
        skipped,
    })
}

fn row(case: usize, method: usize, reference: &Timed, timed: &Timed) -> Row {
    let (r, t) = (&reference.trace, &timed.trace);
    Row {
        case,
        method,
        seconds: timed.seconds,
        steps: timed.steps,
        deepest_overlap: timed.deepest_overlap,
        escaped: timed.escaped,
        comparison: compare(r, t),
        first_collision_matches: first_collision(r) == first_collision(t),
        object_contact_matches: saw_collision(r, 0, 1) == saw_collision(t, 0, 1),
    }
}

/// Runs the study and writes `accuracy-cost.md`, `.csv` and `.png` into `out`.
pub fn run(out: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let study = run_study()?;
    let md = out.join("accuracy-cost.md");
    std::fs::write(&md, report::markdown(&study))
        .with_context(|| format!("writing {}", md.display()))?;
    let csv = out.join("accuracy-cost.csv");
    std::fs::write(&csv, report::csv(&study))
        .with_context(|| format!("writing {}", csv.display()))?;
    let png = out.join("accuracy-cost.png");
    plot::draw(&study, &png).with_context(|| format!("drawing {}", png.display()))?;
    println!(
        "wrote {}, {} and {}",
        md.display(),
        csv.display(),
        png.display()
    );
    Ok(())
}
