//! The study's tables, as Markdown and CSV.

use std::fmt::Write;

use super::methods::{Method, STEPS};
use super::metrics::{median, SEQUENCE_LEN};
use super::workload::{Category, RACK_GAP};
use super::{Row, Study};

/// Aggregates of one method over a set of shots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    pub shots: usize,
    /// Mean over the shots of the per-shot mean position error (mm).
    pub mean_mm: f64,
    /// Largest position error of any ball in any shot (mm).
    pub max_mm: f64,
    pub sequence_share: f64,
    pub pockets_share: f64,
    /// Median CPU time per shot (µs).
    pub median_us: f64,
}

pub fn summarize<'a>(rows: impl Iterator<Item = &'a Row>) -> Summary {
    let rows: Vec<&Row> = rows.collect();
    let n = rows.len().max(1) as f64;
    let share = |f: &dyn Fn(&Row) -> bool| rows.iter().filter(|r| f(r)).count() as f64 / n;
    let times: Vec<f64> = rows.iter().map(|r| r.seconds * 1e6).collect();
    Summary {
        shots: rows.len(),
        mean_mm: rows.iter().map(|r| r.comparison.mean_mm).sum::<f64>() / n,
        max_mm: rows.iter().map(|r| r.comparison.max_mm).fold(0.0, f64::max),
        sequence_share: share(&|r| r.comparison.sequence_matches),
        pockets_share: share(&|r| r.comparison.pockets_match),
        median_us: median(&times),
    }
}

impl Study {
    /// The rows of method `m` on shots of the given categories.
    pub fn rows_of(&self, m: usize, categories: &[Category]) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| r.method == m && categories.contains(&self.cases[r.case].category))
            .collect()
    }

    fn count(&self, m: usize, category: Category, f: impl Fn(&Row) -> bool) -> (usize, usize) {
        let rows = self.rows_of(m, &[category]);
        (rows.iter().filter(|r| f(r)).count(), rows.len())
    }
}

fn pct(x: f64) -> String {
    format!("{:.0}%", 100.0 * x)
}

fn mm(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x < 0.01 {
        format!("{x:.1e}")
    } else if x < 10.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.0}")
    }
}

fn us(x: f64) -> String {
    if x < 10.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.0}")
    }
}

fn summary_table(out: &mut String, study: &Study, categories: &[Category]) {
    out.push_str("| method | step | mean error (mm) | max error (mm) | first 10 contacts match | pocketed set matches | median CPU per shot (µs) |\n");
    out.push_str("|---|---|---:|---:|---:|---:|---:|\n");
    for (m, method) in study.methods.iter().enumerate() {
        let s = summarize(study.rows_of(m, categories).into_iter());
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} |",
            method.family(),
            method.step_label(),
            mm(s.mean_mm),
            mm(s.max_mm),
            pct(s.sequence_share),
            pct(s.pockets_share),
            us(s.median_us)
        );
    }
}

/// The largest step of `family` (TOI or not) at which `ok` holds for every shot of
/// `category`, and every finer step too.
fn step_needed(study: &Study, toi: bool, category: Category, ok: &dyn Fn(&Row) -> bool) -> String {
    let mut best = "none of these".to_string();
    for &(dt, label) in STEPS.iter().rev() {
        let m = study
            .methods
            .iter()
            .position(|x| matches!(x, Method::Fixed(f) if f.toi == toi && f.dt == dt));
        let Some(m) = m else { continue };
        if study.rows_of(m, &[category]).into_iter().all(ok) {
            best = label.to_string();
        } else {
            break;
        }
    }
    best
}

pub fn markdown(study: &Study) -> String {
    let mut out = String::new();
    let all = Category::ALL;
    let breaks = study.cases.iter().filter(|c| c.category.is_break()).count();
    let _ = writeln!(out, "# Accuracy and cost: measured tables\n");
    let _ = writeln!(
        out,
        "Produced by `breakshot-sim accuracy-cost`. {} shots ({} of them breaks), each simulated by \
         the event-based engine (the reference) and by fixed-step integration at {} steps, with and \
         without the time-of-impact (TOI) correction. All shots use the ideal ball–ball model \
         (normal components exchanged) so that every method models the same physics; friction, \
         spin and the cushion model are the engine's. Errors are final-position distances to the \
         reference, a pocketed ball counting as lying at its pocket's centre. CPU times are \
         medians of one thread's wall-clock time per shot on the machine that ran the study.\n",
        study.cases.len(),
        breaks,
        STEPS.len()
    );
    let _ = writeln!(
        out,
        "The engine has no precision setting (no root-solver tolerance or polishing switch): \
         every event time is found to the last bit, so it appears once.\n"
    );
    if !study.skipped.is_empty() {
        let _ = writeln!(
            out,
            "Left out because the event-based engine could not simulate them (so there is no \
             reference):\n"
        );
        for (case, why) in &study.skipped {
            let _ = writeln!(out, "- {}: {}", case.name, why);
        }
        out.push('\n');
    }
    let _ = writeln!(out, "## All shots\n");
    summary_table(&mut out, study, &all);
    for category in all {
        let n = study
            .cases
            .iter()
            .filter(|c| c.category == category)
            .count();
        let _ = writeln!(out, "\n## {} ({} shots)\n", category.name(), n);
        summary_table(&mut out, study, &[category]);
    }

    let _ = writeln!(out, "\n## Where fixed steps break down\n");
    let _ = writeln!(
        out,
        "Thin cuts: the cue ball should graze ball 1 (impact parameter 1.90 R to 1.99 R). Breaks: \
         the cue ball arrives at about 12 m/s and moves {:.0} mm per step at 60 Hz; the rack's \
         balls are {:.1} mm apart.\n",
        12.3 / 60.0 * 1e3,
        RACK_GAP * 1e3
    );
    out.push_str("| method | step | thin cuts with the wrong contact | breaks with the wrong first collision | deepest overlap at detection in breaks, median (mm) | breaks with the wrong pocketed set | breaks with the wrong first 10 contacts | balls that left the table (all shots) |\n");
    out.push_str("|---|---|---:|---:|---:|---:|---:|---:|\n");
    for (m, method) in study.methods.iter().enumerate() {
        if *method == Method::Event {
            continue;
        }
        let (thin_bad, thin_n) = study.count(m, Category::ThinCut, |r| !r.object_contact_matches);
        let mut bad_first = 0;
        let mut bad_pockets = 0;
        let mut bad_sequence = 0;
        let mut overlaps = Vec::new();
        for category in [Category::Break8, Category::Break9] {
            bad_first += study.count(m, category, |r| !r.first_collision_matches).0;
            bad_pockets += study.count(m, category, |r| !r.comparison.pockets_match).0;
            bad_sequence += study
                .count(m, category, |r| !r.comparison.sequence_matches)
                .0;
            overlaps.extend(
                study
                    .rows_of(m, &[category])
                    .iter()
                    .map(|r| r.deepest_overlap * 1e3),
            );
        }
        let escaped: usize = study.rows_of(m, &all).iter().map(|r| r.escaped).sum();
        let _ = writeln!(
            out,
            "| {} | {} | {thin_bad} of {thin_n} | {bad_first} of {breaks} | {} | {bad_pockets} of {breaks} | {bad_sequence} of {breaks} | {escaped} |",
            method.family(),
            method.step_label(),
            mm(median(&overlaps)),
        );
    }

    let _ = writeln!(out, "\n## The step it takes to get each right\n");
    let _ = writeln!(
        out,
        "The largest step (of those tried) at which every shot of the kind is right, and every \
         finer step too. \"none of these\" means that even 0.01 ms gets some shot wrong.\n"
    );
    out.push_str("| shots | method | first 10 contacts | pocketed set | mean error < 1 mm |\n");
    out.push_str("|---|---|---|---|---|\n");
    for category in all {
        for toi in [false, true] {
            let family = if toi {
                "fixed step + TOI"
            } else {
                "fixed step"
            };
            let _ = writeln!(
                out,
                "| {} | {family} | {} | {} | {} |",
                category.name(),
                step_needed(study, toi, category, &|r| r.comparison.sequence_matches),
                step_needed(study, toi, category, &|r| r.comparison.pockets_match),
                step_needed(study, toi, category, &|r| r.comparison.mean_mm < 1.0),
            );
        }
    }

    let _ = writeln!(out, "\n## The cost of each effect\n");
    let _ = writeln!(
        out,
        "{} of the breaks above, simulated by the engine with a horizon of {} s, switching \
         on one effect more at each rung. The frictionless rungs run until the horizon; the \
         others stop when the balls do.\n",
        study.effects.shots,
        super::effects::HORIZON
    );
    for why in &study.effects.left_out {
        let _ = writeln!(out, "- left out: {why}");
    }
    if !study.effects.left_out.is_empty() {
        out.push('\n');
    }
    out.push_str(
        "| model | median CPU per shot (µs) | mean events per shot | median CPU per event (ns) |\n",
    );
    out.push_str("|---|---:|---:|---:|\n");
    for rung in &study.effects.rungs {
        let _ = writeln!(
            out,
            "| {} | {} | {:.0} | {:.0} |",
            rung.name,
            us(rung.median_shot * 1e6),
            rung.mean_events,
            rung.per_event * 1e9
        );
    }
    let d = &study.disabled;
    let _ = writeln!(out, "\n## A disabled effect costs nothing\n");
    let _ = writeln!(
        out,
        "The same open-cloth shot (9-ball break 0, moved to the open cloth: {} events there), \
         on the open table and on a 9 ft table with `cushions` and `pockets` off, timed \
         interleaved in the same run, each table with its own simulator. The two runs give \
         {} events, and final positions within {:.1e} m of each other (the rounding of \
         adding and removing the table's offset).\n",
        d.events_open,
        if d.same_events {
            "bit-identical"
        } else {
            "DIFFERENT"
        },
        d.position_difference
    );
    out.push_str("| table | events | median CPU per shot (µs) |\n|---|---:|---:|\n");
    let _ = writeln!(
        out,
        "| open | {} | {:.3} |",
        d.events_open,
        d.median_open * 1e6
    );
    let _ = writeln!(
        out,
        "| 9 ft, cushions and pockets off | {} | {:.3} |",
        d.events_9ft,
        d.median_9ft * 1e6
    );
    let _ = writeln!(out, "\nRatio 9 ft / open: {:.3}.", d.ratio);
    let _ = writeln!(
        out,
        "\nSequence: the first {SEQUENCE_LEN} ball–ball collisions, ball–cushion collisions and \
         pockets, in order."
    );
    out
}

pub fn csv(study: &Study) -> String {
    let mut out = String::from(
        "method,step_s,toi,category,shot,mean_error_mm,max_error_mm,sequence_match,pockets_match,\
         first_collision_match,cpu_us,steps,deepest_overlap_mm,escaped\n",
    );
    for r in &study.rows {
        let method = &study.methods[r.method];
        let case = &study.cases[r.case];
        let toi = matches!(method, Method::Fixed(f) if f.toi);
        let _ = writeln!(
            out,
            "{},{},{},{},\"{}\",{:.6},{:.6},{},{},{},{:.3},{},{:.6},{}",
            method.family(),
            method.dt().map_or(String::new(), |dt| format!("{dt:e}")),
            toi,
            category_key(case.category),
            case.name.replace('"', "'"),
            r.comparison.mean_mm,
            r.comparison.max_mm,
            r.comparison.sequence_matches,
            r.comparison.pockets_match,
            r.first_collision_matches,
            r.seconds * 1e6,
            r.steps,
            r.deepest_overlap * 1e3,
            r.escaped
        );
    }
    out
}

fn category_key(c: Category) -> &'static str {
    match c {
        Category::SingleNoSpin => "single",
        Category::SingleSpin => "single_spin",
        Category::Stun => "stun",
        Category::HalfBall => "half_ball",
        Category::ThinCut => "thin_cut",
        Category::Cushion => "cushion",
        Category::Break8 => "break_8ball",
        Category::Break9 => "break_9ball",
    }
}
