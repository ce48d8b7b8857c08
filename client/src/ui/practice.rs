//! The practice screen: a practice table of the rules, played through the local link.

use breakshot_client::play::drill::{climb, Drill, Score};
use breakshot_client::play::position;
use breakshot_client::play::{
    next_level, Advice, Advisor, Aim, Context, Controls, CueMode, Drag, GameEvent, GameFlow,
    GameLink, History, InputFrame, Intent, Key, LocalLink, Position, Request, Tool,
};
use breakshot_client::view::aids::{self, AidToggles, Prediction};
use breakshot_client::view::hud::Connection;
use breakshot_client::view::{Frame, Layout, Orientations, Playback, Rect};
use breakshot_shared::ai::Level;
use breakshot_shared::hash::{hash_hex, state_hash};
use breakshot_shared::physics::{MotionState, Shot, Simulator};
use breakshot_shared::rules::{Command, EightBallRules, Game, Variant};
use breakshot_shared::scene::Scene;
use macroquad::prelude::*;

use super::draw::BallsShown;
use super::table_view::TableView;
use super::{draw, panel, trays, Start, Step};

/// A drill being played: its rungs' tables, the rung played, and the score so far (the
/// remembered one to begin).
struct DrillRun {
    drill: Drill,
    starts: Vec<Game>,
    rung: usize,
    score: Score,
    /// The trajectory of the attempt playing (the replica plays it back).
    attempt: Option<breakshot_shared::physics::Outcome>,
}

pub struct PracticeScreen {
    /// Where the table's commands are checked; a reset starts its first table again.
    link: LocalLink,
    /// The table as the rules leave it, and the shot being shown.
    flow: GameFlow,
    /// The balls' names, index = ball.
    ids: Vec<String>,
    /// Dragging moves the cue ball (the rules allow it any time in practice; the screen
    /// offers it after a scratch, at the start of a rack, or on H).
    placing: bool,
    frame: Frame,
    controls: Controls,
    toggles: AidToggles,
    sim: Simulator,
    /// The shot the aids were computed for, and what they show.
    predicted: Option<(Shot, Prediction)>,
    debug: bool,
    message: String,
    shots: u32,
    frame_ms: f64,
    /// How each ball is turned, for drawing.
    turns: Orientations,
    view: TableView,
    /// The tables before each shot, for undo, redo and again.
    history: History,
    /// The hash of the table at rest last reported (`BREAKSHOT_REPORT`).
    reported: Option<u64>,
    /// The computer's advice being searched, a few simulations a frame.
    advisor: Option<Advisor>,
    /// The advice found for the table shown, with its predicted paths.
    advice: Option<(Advice, Prediction)>,
    /// Whose noise the advice's chance is for (I again on an advice: the next level).
    advice_level: Level,
    /// The last shot pocketed nothing: I then advises on the table it was played from.
    missed: bool,
    /// Setting up the position (F): the mouse drags any ball instead of aiming.
    arranging: bool,
    /// The ball being dragged while arranging.
    moving: Option<usize>,
    /// Where it would go.
    drag_to: Option<::glam::DVec2>,
    /// The drill played, if any: each shot is an attempt, judged, then the table is set up
    /// again.
    drill: Option<DrillRun>,
}

/// Simulations the advice's search may run each frame: the window keeps drawing while it
/// thinks, natively and in the browser alike (one takes well under a millisecond).
const ADVICE_PER_FRAME: usize = 6;

impl PracticeScreen {
    /// Practice on `scene`, or on a rack from `seed` when there is none.
    pub fn new(scene: Option<Scene>, seed: u64) -> anyhow::Result<PracticeScreen> {
        PracticeScreen::open(scene, None, seed)
    }

    /// `drill` played: each shot an attempt, the table set up again after it.
    pub fn drill(drill: Drill) -> anyhow::Result<PracticeScreen> {
        PracticeScreen::open(Some(drill.first().scene.clone()), Some(drill), 0)
    }

    fn open(
        scene: Option<Scene>,
        drill: Option<Drill>,
        seed: u64,
    ) -> anyhow::Result<PracticeScreen> {
        let game = match &scene {
            Some(s) => Game::practice(s)?,
            None => Game::practice_rack(Variant::EightBall(EightBallRules::Wpa), seed)?,
        };
        // A scene's strike is the set-up the cue starts with.
        let aim = scene
            .as_ref()
            .and_then(|s| s.to_shot().ok()?.strike)
            .map(|(_, strike)| Aim::from_strike(&strike))
            .unwrap_or_default();
        let ids = game.ball_ids();
        let frame = Frame::new(game.table(), game.balls());
        if let Some(drill) = &drill {
            super::report(&format!("practice drill {}", drill.name));
        }
        let drill = match drill {
            None => None,
            Some(drill) => Some(DrillRun {
                score: super::data_dir()
                    .map(|d| breakshot_client::memory::drill_score(&d, &drill.name))
                    .unwrap_or_default(),
                starts: drill
                    .rungs
                    .iter()
                    .map(|r| Game::practice(&r.scene))
                    .collect::<Result<_, _>>()?,
                rung: 0,
                drill,
                attempt: None,
            }),
        };
        let message = match &drill {
            Some(run) => format!("Drill: {}  |  {}", run.drill.name, run.score.line()),
            None => "Aim with the mouse, pull back or press Space to shoot".into(),
        };
        let mut link = LocalLink::from_game(game);
        let mut flow = GameFlow::new(Connection::Offline);
        while let Some(event) = link.poll() {
            flow.handle(event);
        }
        Ok(PracticeScreen {
            link,
            flow,
            ids,
            placing: scene.is_none(),
            frame,
            controls: Controls::new(aim),
            toggles: AidToggles::default(),
            sim: Simulator::new(),
            predicted: None,
            debug: false,
            message,
            shots: 0,
            frame_ms: 0.0,
            turns: Orientations::new(),
            view: TableView::new(),
            history: History::new(),
            reported: None,
            advisor: None,
            advice: None,
            advice_level: Level::new(3),
            missed: false,
            arranging: false,
            moving: None,
            drag_to: None,
            drill,
        })
    }

    /// The table as the rules left it (every practice screen has one).
    fn game(&self) -> Option<&Game> {
        self.flow.game()
    }

    fn busy(&self) -> bool {
        self.flow.shot().is_some()
    }

    fn layout(&self) -> Layout {
        Layout::new(screen_width(), screen_height(), self.frame)
    }

    fn cue_mode(&self) -> CueMode {
        if self.busy() || self.arranging {
            CueMode::Watching
        } else if self.placing {
            CueMode::InHand
        } else {
            CueMode::Aiming
        }
    }

    /// Sends `command` through the link and applies what it says; the rules' refusal, if
    /// any, becomes the message.
    fn send(&mut self, command: Command) -> bool {
        let Some(game) = self.flow.game().cloned() else {
            return false;
        };
        self.link.send(&game, game.to_move(), command);
        let mut accepted = false;
        while let Some(event) = self.link.poll() {
            if let breakshot_client::play::GameEvent::Refused(why) = &event {
                super::report(&format!("practice refused: {why}"));
                self.message = why.clone();
            } else {
                accepted = true;
            }
            self.flow.handle(event);
        }
        accepted
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * input.dt * 1000.0;
        let Some(game) = self.game().cloned() else {
            return Step::Open(Start::Menu);
        };
        // Before Space can skip the shot: a skipped shot has ended too.
        let was_busy = self.busy();
        let layout = self.layout();
        let cue = game.balls()[game.cue_ball()].pos;
        let r = game.params().ball_radius;
        let aiming = !self.busy();
        self.view
            .update(input, cue, self.controls.aim.dir(), aiming);
        let input = &self.view.pointer(input, &layout, r);
        let ctx = Context {
            layout: &layout,
            cue,
            radius: r,
            cue_mode: self.cue_mode(),
        };
        if self.busy() && input.pressed.contains(&Key::Shoot) {
            self.flow.skip();
        }
        if let Some(dropped) = input.dropped.last() {
            self.open_dropped(dropped);
        }
        if self.arranging && !self.busy() {
            self.arrange(input, &layout, &game);
        }
        let intents = self.controls.update(input, &ctx, &|p| {
            game.legal_cue_placement(p.to_array()).is_ok()
        });
        for intent in intents {
            match intent {
                Intent::Shoot(strike) => {
                    if self.send(Command::Shot { strike, call: None }) {
                        self.history.shot(game.clone(), strike);
                        if let Some(run) = self.drill.as_mut() {
                            run.attempt = self.flow.shot().map(|pb| pb.outcome().clone());
                        }
                        self.advice = None;
                        self.advisor = None;
                        self.shots += 1;
                        self.placing = false;
                        self.controls.shot_played();
                        self.message = format!("Shot {} at {:.1} m/s", self.shots, strike.speed);
                        super::report(&format!(
                            "practice shot {} dir={:.4},{:.4} tip={:.3},{:.3} elevation={:.2}",
                            self.shots,
                            strike.dir.x,
                            strike.dir.y,
                            strike.tip.x,
                            strike.tip.y,
                            strike.elevation_deg
                        ));
                    }
                }
                Intent::PlaceCueBall(pos) => {
                    self.send(Command::PlaceCueBall { pos });
                }
                Intent::Toggle(aid) => self.toggles.toggle(aid),
                Intent::ToggleDebug => self.debug = !self.debug,
                Intent::TakeBallInHand if !self.busy() => self.placing = true,
                Intent::TakeBallInHand => {}
                Intent::Rerack => {
                    self.link.rematch();
                    while let Some(event) = self.link.poll() {
                        self.flow.handle(event);
                    }
                    self.history.clear();
                    self.message = "Table reset".into();
                }
                Intent::Tool(Tool::Undo) => {
                    let to = self.history.undo(game.clone());
                    self.restore(to, false, "Shot taken back", "No shot to take back");
                }
                Intent::Tool(Tool::Redo) => {
                    let to = self.history.redo(game.clone());
                    self.restore(to, false, "Shot played again", "No shot to play again");
                }
                Intent::Tool(Tool::Again) => {
                    let to = self.history.again(game.clone());
                    self.restore(to, true, "The last shot set up again", "No shot yet");
                }
                Intent::Back => return Step::Open(Start::Menu),
                Intent::Tool(Tool::Advice) if !self.busy() => self.ask_advice(&game),
                Intent::Tool(Tool::SavePosition) => self.save(&game),
                Intent::Tool(Tool::Arrange) => {
                    self.arranging = !self.arranging;
                    self.moving = None;
                    super::report(&format!("practice arranging {}", self.arranging));
                    self.message = if self.arranging {
                        "Setting up: drag any ball; off the cloth takes it off; N puts the next one back at the mouse; F: done".into()
                    } else {
                        "Position set: aim and shoot".into()
                    };
                }
                Intent::Tool(Tool::PlayAdvice) => {
                    if let Some((advice, _)) = &self.advice {
                        self.controls.aim = Aim::from_strike(&advice.strike);
                        self.message = format!(
                            "Set: {}  |  Space plays it",
                            advice.summary(self.advice_level)
                        );
                        super::report("practice advice set");
                    }
                }
                Intent::Tool(Tool::Advice) => {}
            }
        }
        self.flow.tick(input.dt);
        if was_busy && !self.busy() && self.scratched() {
            // The rules put the cue ball back: offer to move it.
            self.placing = true;
        }
        if was_busy && !self.busy() && self.drill.is_some() {
            self.judge_attempt();
        } else if was_busy && !self.busy() {
            self.missed = self.pocketed_nothing();
            if self.missed {
                super::report("practice missed");
                self.message = "Missed: I shows what the computer would have played".into();
            }
        }
        self.think();
        self.refresh_prediction();
        self.report_table();
        Step::Stay
    }

    /// Arranging: a press on a ball picks it up, the release puts it down there (off the
    /// cloth: off the table); N puts the first ball off the table back at the mouse. Each
    /// change is the rules' `PlaceBall`, refused with their reason where a ball cannot lie.
    fn arrange(&mut self, input: &InputFrame, layout: &Layout, game: &Game) {
        let at = layout.to_scene(input.mouse);
        let r = game.params().ball_radius;
        if input.left_pressed {
            self.moving = game.balls().iter().position(|b| {
                b.motion != MotionState::Pocketed && (b.pos - at).length() <= 1.5 * r
            });
        }
        let put = |pos: Option<[f64; 2]>, ball: usize| Command::PlaceBall {
            ball: ball as u8,
            pos,
        };
        let mut command = None;
        let released = self.moving.filter(|_| input.left_released);
        if let Some(ball) = released {
            self.moving = None;
            let on_cloth = layout.cloth.contains(input.mouse) && at.is_finite();
            command = Some(put(on_cloth.then(|| at.to_array()), ball));
        }
        self.drag_to = self.moving.map(|_| at);
        if input.pressed.contains(&Key::Next) {
            let off = game
                .balls()
                .iter()
                .position(|b| b.motion == MotionState::Pocketed);
            match off {
                Some(ball) => command = Some(put(Some(at.to_array()), ball)),
                None => self.message = "Every ball of the set is on the table".into(),
            }
        }
        if let Some(command) = command {
            if self.send(command) {
                self.history.changed(game.clone());
                self.advice = None;
                self.message = "Ball placed (U takes it back)".into();
                super::report("practice ball placed");
            }
        }
    }

    /// O: the table as a scene file in the data directory and as a code on the clipboard.
    fn save(&mut self, game: &Game) {
        let (json, code) = match position::written(game) {
            Ok(written) => written,
            Err(why) => {
                self.message = format!("Cannot keep this position: {why}");
                return;
            }
        };
        super::invite::copy(&code);
        let kept = super::data_dir().map(|dir| {
            let dir = dir.join("positions");
            let path = dir.join(format!("{}.json", hash_hex(state_hash(game.balls()))));
            std::fs::create_dir_all(&dir)
                .and_then(|()| std::fs::write(&path, &json))
                .map(|()| path)
        });
        self.message = match kept {
            Some(Ok(path)) => {
                super::report(&format!("practice saved {} {code}", path.display()));
                format!("Kept as {} and copied as {code}", path.display())
            }
            Some(Err(e)) => format!("Copied as {code}; cannot write the file: {e}"),
            None => format!("Copied as {code}"),
        };
    }

    /// A scene file or a file holding a code dropped on the window: its table, if the rules
    /// accept it; otherwise the reason, and the table stays as it was.
    fn open_dropped(&mut self, bytes: &[u8]) {
        let text = String::from_utf8_lossy(bytes);
        match position::open(&text) {
            Ok((_, game)) => {
                self.ids = game.ball_ids();
                self.frame = Frame::new(game.table(), game.balls());
                self.link = LocalLink::from_game(game);
                while let Some(event) = self.link.poll() {
                    self.flow.handle(event);
                }
                self.history.clear();
                self.advice = None;
                self.advisor = None;
                self.message = "Position opened".into();
                super::report("practice position opened");
            }
            Err(why) => {
                self.message = format!("Not opened: {why}");
                super::report(&format!("practice position refused: {why}"));
            }
        }
    }

    /// A drill's attempt has played out: judged by the goal, counted, remembered, and the
    /// drill's table set up again for the next one.
    fn judge_attempt(&mut self) {
        let (Some(run), Some(game)) = (self.drill.as_mut(), self.flow.game()) else {
            return;
        };
        let outcome = run.attempt.take();
        let made = outcome.is_some_and(|o| run.drill.judge(run.rung, &o, game.cue_ball()));
        run.score.attempt(made);
        if let Some(data) = super::data_dir() {
            let kept =
                breakshot_client::memory::remember_drill_score(&data, &run.drill.name, &run.score);
            if let Err(e) = kept {
                tracing::warn!(error = %e, "cannot keep the drill's score");
            }
        }
        let said = if made { "made" } else { "missed" };
        let mut line = run.score.line();
        super::report(&format!("drill {said}: {line}"));
        let rungs = run.starts.len();
        if rungs > 1 {
            run.rung = climb(run.rung, made, rungs);
            super::report(&format!("drill rung {} of {rungs}", run.rung + 1));
            line = format!("rung {} of {rungs}; {line}", run.rung + 1);
        }
        let start = run.starts[run.rung].clone();
        self.flow.handle(GameEvent::Started(Box::new(start)));
        self.placing = false;
        self.message = format!("{}: {said}  |  {line}", run.drill.name);
    }

    /// Did the last shot pocket no object ball?
    fn pocketed_nothing(&self) -> bool {
        self.last_pocketed()
            .is_some_and(|mut cue| cue.all(|is_cue| is_cue))
    }

    /// For each ball the last shot pocketed, whether it was the cue ball; `None` before a
    /// shot has been judged.
    fn last_pocketed(&self) -> Option<impl Iterator<Item = bool> + '_> {
        let (game, verdict) = (self.game()?, self.flow.last_verdict.as_ref()?);
        let cue = game.cue_ball();
        let shot = verdict.shot.as_ref()?;
        Some(
            shot.pocketed
                .iter()
                .map(move |&(b, _)| usize::from(b) == cue),
        )
    }

    /// I: the computer's shot on this table (after a miss: on the table the shot was
    /// played from, which comes back); I again once it is shown: the same at the next level.
    /// In a drill that carries an example, the example is set on the cue instead: the
    /// computer's search judges pots alone, and a drill asks for more (a zone, cushions, a
    /// three-cushion point).
    fn ask_advice(&mut self, game: &Game) {
        let rung = |run: &DrillRun| run.drill.rungs.get(run.rung).and_then(|r| r.example);
        if let Some(example) = self.drill.as_ref().and_then(rung) {
            self.controls.aim = Aim::from_strike(&example);
            self.message = format!(
                "A way to make it: {:.1} m/s at {:.1} deg, tip ({:.2}, {:.2})  |  Space plays it",
                example.speed,
                libm::atan2(example.dir.y, example.dir.x).to_degrees(),
                example.tip.x,
                example.tip.y
            );
            super::report("practice drill example set");
            return;
        }
        let mut table = game.clone();
        let mut missed = None;
        if std::mem::take(&mut self.missed) {
            let back = self.history.undo(game.clone());
            if let Some(back) = back {
                table = back.game.clone();
                missed = back.strike;
                self.restore(Some(back), false, "Shot taken back", "");
            }
        } else if self.advice.is_some() {
            self.advice_level = next_level(self.advice_level);
        }
        self.advice = None;
        self.advisor = None;
        // After a miss the shot missed is measured too, for "that shot: 31 %" beside the advice.
        let start = |request| match missed {
            Some(strike) => Advisor::after_miss(request, strike),
            None => Advisor::start(request),
        };
        match Request::for_table(&table, self.advice_level).and_then(start) {
            Ok(advisor) => {
                if let Some(request) = advisor.request() {
                    super::report(&format!(
                        "practice advice asked: {}",
                        request.command_line("SCENE")
                    ));
                }
                self.advisor = Some(advisor);
            }
            Err(why) => self.message = format!("No advice: {why}"),
        }
    }

    /// Moves the advice's search on by a frame's share; shows the advice once found.
    fn think(&mut self) {
        let Some(advisor) = self.advisor.as_mut() else {
            return;
        };
        let Some(done) = advisor.step(ADVICE_PER_FRAME).cloned() else {
            self.message = format!(
                "The computer is thinking ({:.0} %)",
                100.0 * advisor.fraction()
            );
            return;
        };
        self.advisor = None;
        let Some(game) = self.game().cloned() else {
            return;
        };
        match done {
            Ok(advice) => {
                let shot = game.shot_for(&advice.strike);
                let prediction =
                    aids::predict(&mut self.sim, &shot, game.cue_ball()).unwrap_or_default();
                self.message = format!("{}  |  J: play it", advice.summary(self.advice_level));
                super::report(&format!(
                    "practice advice {} {} {} {} {}",
                    advice.strike.speed,
                    advice.strike.dir.x,
                    advice.strike.dir.y,
                    advice.p_success,
                    advice.trials
                ));
                if let Some(played) = advice.played {
                    super::report(&format!(
                        "practice advice after a miss: that shot {} of {}",
                        played.share, played.trials
                    ));
                }
                self.advice = Some((advice, prediction));
            }
            Err(why) => self.message = format!("No advice: {why}"),
        }
    }

    /// Puts the table back to `to` (the replica's own game, so to the bit); with `aim`, the
    /// cue as it was set for the shot played from there too.
    fn restore(&mut self, to: Option<Position>, aim: bool, done: &str, none: &str) {
        let Some(to) = to else {
            self.message = none.into();
            return;
        };
        self.flow.handle(GameEvent::Started(Box::new(to.game)));
        if let (true, Some(strike)) = (aim, to.strike) {
            self.controls.aim = Aim::from_strike(&strike);
        }
        self.placing = false;
        self.predicted = None;
        self.advice = None;
        self.advisor = None;
        self.missed = false;
        self.message = format!(
            "{done} ({} behind, {} ahead)",
            self.history.behind(),
            self.history.ahead()
        );
        super::report(&format!("practice {}", done.to_lowercase()));
    }

    /// Says the table's hash each time it comes to rest changed, for tests to observe.
    fn report_table(&mut self) {
        let Some(game) = self.game().filter(|_| !self.busy()) else {
            return;
        };
        let hash = state_hash(game.balls());
        if self.reported != Some(hash) {
            self.reported = Some(hash);
            super::report(&format!("practice table {}", hash_hex(hash)));
        }
    }

    /// Did the last shot pocket the cue ball (which the rules then put back)?
    fn scratched(&self) -> bool {
        self.last_pocketed()
            .is_some_and(|mut cue| cue.any(|is_cue| is_cue))
    }

    /// Re-simulates the aids when the shot being set up changes.
    fn refresh_prediction(&mut self) {
        let Some(game) = self.game().filter(|_| !self.busy()) else {
            self.predicted = None;
            return;
        };
        let (shot, cue) = (game.shot_for(&self.controls.aim.strike()), game.cue_ball());
        if self.predicted.as_ref().is_some_and(|(s, _)| *s == shot) {
            return;
        }
        let prediction = aids::predict(&mut self.sim, &shot, cue).unwrap_or_default();
        self.predicted = Some((shot, prediction));
    }

    /// The shot being shown, if any.
    pub fn shot(&self) -> Option<&Playback> {
        self.flow.shot()
    }

    pub fn draw(&mut self) {
        let Some(game) = self.game().cloned() else {
            return;
        };
        self.turns.follow(self.flow.shot());
        let layout = self.layout();
        let r = game.params().ball_radius;
        let busy = self.busy();
        let pen = self.view.pen(&layout, r, self.flow.shot(), game.table());
        draw::table(&pen, game.table());
        let shown = self.flow.balls();
        let cue_index = game.cue_ball();
        let cue = shown[cue_index].pos;
        let dragging = match self.controls.drag {
            Drag::CueBall { at } => Some((at, game.legal_cue_placement(at.to_array()).is_ok())),
            _ => None,
        };
        if !busy && dragging.is_none() {
            if let Some((_, pred)) = &self.predicted {
                let object = pred
                    .first_hit
                    .and_then(|b| self.ids.get(b))
                    .map_or("", |s| s.as_str());
                draw::aids(&pen, pred, self.toggles, r, object);
            }
        }
        if let (false, Some((advice, pred))) = (busy, &self.advice) {
            // The advised shot's paths, all of them, and the spot the cue ball plays for.
            let all = AidToggles {
                aim_line: true,
                ghost_ball: true,
                paths: true,
            };
            let object = pred
                .first_hit
                .and_then(|b| self.ids.get(b))
                .map_or("", |s| s.as_str());
            draw::aids(&pen, pred, all, r, object);
            if let Some(leave) = advice.leave {
                draw::ring(&pen, leave, r, YELLOW);
            }
        }
        let balls = BallsShown {
            ids: &self.ids,
            states: &shown,
            radius: r,
            skip: dragging.map(|_| cue_index),
            turns: &self.turns,
        };
        draw::balls(&pen, &balls);
        if let Some(to) = self.drag_to {
            draw::ring(&pen, to, r, WHITE);
        }
        if !busy && self.placing {
            draw::in_hand(&pen, layout.cloth, dragging, r);
        }
        if !busy && dragging.is_none() {
            draw::cue_stick(&pen, cue, &self.controls.aim, r);
        }
        trays::tray(&layout, &self.ids, &self.flow.tray(), r);
        panel::panel(&layout, &self.controls.aim, Some(self.controls.keep_spin));
        self.hud(&layout, &game);
        if self.debug {
            self.debug_overlay(&layout);
        }
    }

    fn hud(&self, layout: &Layout, game: &Game) {
        draw_rectangle(
            layout.hud.x,
            layout.hud.y,
            layout.hud.w,
            layout.hud.h,
            Color::new(0.0, 0.0, 0.0, 0.5),
        );
        let state = if self.busy() {
            "balls moving (Space: skip)"
        } else if self.arranging {
            "setting up: drag any ball (F: done)"
        } else if self.placing {
            "ball in hand: drag the cue ball"
        } else {
            "your shot"
        };
        // The state across the bar, the keys in the line over the table (a practice has
        // no status of its own to say there).
        let bar = layout.hud;
        let across = Rect::new(
            layout.players[0].x,
            bar.y,
            bar.w - 2.0 * layout.players[0].x,
            bar.h,
        );
        draw::label_in(
            &format!("Practice  |  {} table  |  {}", game.table().name(), state),
            across,
            20.0,
            draw::Align::Left,
            WHITE,
        );
        let hint = "W/S elevation  |  A G P aids  |  V view  |  L trail  |  H in hand  |  U undo  Y redo  B again  |  I advice  J play it  |  F set up  O keep  |  R reset  |  Esc menu";
        draw::label_in(hint, layout.status, 16.0, draw::Align::Left, LIGHTGRAY);
        draw::label_in(
            &self.message,
            layout.footer,
            18.0,
            draw::Align::Left,
            LIGHTGRAY,
        );
    }

    fn debug_overlay(&self, layout: &Layout) {
        let last_hash = self
            .flow
            .last_verdict
            .as_ref()
            .and_then(|v| v.shot.as_ref())
            .map(|s| s.hash);
        let mut lines = vec![
            format!("frame {:.1} ms", self.frame_ms),
            format!(
                "window {:.0}x{:.0}, {:.1} px/m",
                layout.screen[0], layout.screen[1], layout.scale
            ),
            format!("shots {}", self.shots),
            format!(
                "aim {:.3} deg, {:.2} m/s, tip ({:.2}, {:.2}), elevation {:.1} deg",
                self.controls.aim.angle.to_degrees(),
                self.controls.aim.speed(),
                self.controls.aim.tip.x,
                self.controls.aim.tip.y,
                self.controls.aim.elevation_deg
            ),
            format!("last hash {}", last_hash.map_or("-".into(), hash_hex)),
        ];
        lines.extend(self.flow.shot().map(draw::debug_shot_line));
        draw::debug_lines(layout, &lines);
    }
}
