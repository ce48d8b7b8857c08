//! The practice screen: a table with no rules and no server.

use breakshot_client::play::{Context, Controls, Drag, InputFrame, Intent, Key, Practice, Stage};
use breakshot_client::view::aids::{self, AidToggles, Prediction};
use breakshot_client::view::{Frame, Layout, Orientations, Playback, Rect};
use breakshot_shared::hash::hash_hex;
use breakshot_shared::physics::{Shot, Simulator, TableKind};
use breakshot_shared::scene::Scene;
use macroquad::prelude::*;

use super::table_view::TableView;
use super::{draw, panel, trays, Start, Step};

pub struct PracticeScreen {
    practice: Practice,
    /// The table as it started, for re-racking.
    initial: Practice,
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
}

impl PracticeScreen {
    pub fn new(scene: Option<Scene>, seed: u64) -> anyhow::Result<PracticeScreen> {
        let practice = match &scene {
            Some(s) => Practice::from_scene(s)?,
            None => Practice::rack(TableKind::NineFoot, seed),
        };
        let aim = practice.scene_aim.unwrap_or_default();
        let frame = Frame::new(practice.table, &practice.balls);
        Ok(PracticeScreen {
            initial: practice.clone(),
            practice,
            frame,
            controls: Controls::new(aim),
            toggles: AidToggles::default(),
            sim: Simulator::new(),
            predicted: None,
            debug: false,
            message: "Aim with the mouse, pull back or press Space to shoot".into(),
            shots: 0,
            frame_ms: 0.0,
            turns: Orientations::new(),
            view: TableView::new(),
        })
    }

    fn layout(&self) -> Layout {
        Layout::new(screen_width(), screen_height(), self.frame)
    }

    fn stage(&self) -> Stage {
        if self.practice.busy() {
            Stage::Watching
        } else if self.practice.in_hand {
            Stage::InHand
        } else {
            Stage::Aiming
        }
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * input.dt * 1000.0;
        let layout = self.layout();
        let cue = self.practice.balls[self.practice.cue].pos;
        let r = self.practice.params.ball_radius;
        let aiming = !self.practice.busy();
        self.view
            .update(input, cue, self.controls.aim.dir(), aiming);
        let input = &self.view.pointer(input, &layout, r);
        let ctx = Context {
            layout: &layout,
            cue,
            radius: self.practice.params.ball_radius,
            stage: self.stage(),
        };
        if self.practice.busy() && input.pressed.contains(&Key::Shoot) {
            self.practice.skip();
        }
        let practice = &self.practice;
        let intents = self
            .controls
            .update(input, &ctx, &|p| practice.placement(p).is_ok());
        for intent in intents {
            match intent {
                Intent::Shoot(strike) => match self.practice.shoot(strike) {
                    Ok(()) => {
                        self.shots += 1;
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
                    Err(e) => self.message = e.to_string(),
                },
                Intent::PlaceCueBall(p) => {
                    if let Err(e) = self.practice.place_cue(p.into()) {
                        self.message = e.to_string();
                    }
                }
                Intent::Toggle(aid) => self.toggles.toggle(aid),
                Intent::ToggleDebug => self.debug = !self.debug,
                Intent::TakeBallInHand if !self.practice.busy() => self.practice.in_hand = true,
                Intent::TakeBallInHand => {}
                Intent::Rerack => {
                    self.practice = self.initial.clone();
                    self.message = "Table reset".into();
                }
                Intent::Back => return Step::Open(Start::Menu),
            }
        }
        self.practice.tick(input.dt, 1.0);
        self.refresh_prediction();
        Step::Stay
    }

    /// Re-simulates the aids when the shot being set up changes.
    fn refresh_prediction(&mut self) {
        if self.practice.busy() {
            self.predicted = None;
            return;
        }
        let shot = self.practice.shot(self.controls.aim.strike());
        if self.predicted.as_ref().is_some_and(|(s, _)| *s == shot) {
            return;
        }
        let prediction = aids::predict(&mut self.sim, &shot, self.practice.cue).unwrap_or_default();
        self.predicted = Some((shot, prediction));
    }

    /// The shot being shown, if any.
    pub fn shot(&self) -> Option<&Playback> {
        self.practice.playback.as_ref()
    }

    pub fn draw(&mut self) {
        self.turns.follow(self.practice.playback.as_ref());
        let layout = self.layout();
        let p = &self.practice;
        let r = p.params.ball_radius;
        let pen = self.view.pen(&layout, r, p.playback.as_ref(), p.table);
        draw::table(&pen, p.table);
        let shown = p.shown_balls();
        let cue = shown[p.cue].pos;
        let dragging = match self.controls.drag {
            Drag::CueBall { at } => Some((at, p.placement(at).is_ok())),
            _ => None,
        };
        if !p.busy() && dragging.is_none() {
            if let Some((_, pred)) = &self.predicted {
                let object = pred
                    .first_hit
                    .and_then(|b| p.ids.get(b))
                    .map_or("", |s| s.as_str());
                draw::aids(&pen, pred, self.toggles, r, object);
            }
        }
        draw::balls(
            &pen,
            &p.ids,
            &shown,
            r,
            dragging.map(|_| p.cue),
            &self.turns,
        );
        if !p.busy() && p.in_hand {
            draw::in_hand(&pen, layout.cloth, dragging, r);
        }
        if !p.busy() && dragging.is_none() {
            draw::cue_stick(&pen, cue, &self.controls.aim, r);
        }
        trays::tray(&layout, &p.ids, &p.shown_pocketed(), r);
        panel::panel(&layout, &self.controls.aim, Some(self.controls.keep_spin));
        self.hud(&layout);
        if self.debug {
            self.debug_overlay(&layout);
        }
    }

    fn hud(&self, layout: &Layout) {
        let p = &self.practice;
        draw_rectangle(
            layout.hud.x,
            layout.hud.y,
            layout.hud.w,
            layout.hud.h,
            Color::new(0.0, 0.0, 0.0, 0.5),
        );
        let state = if p.busy() {
            "balls moving (Space: skip)"
        } else if p.in_hand {
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
            &format!("Practice  |  {} table  |  {}", p.table.name(), state),
            across,
            20.0,
            draw::Align::Left,
            WHITE,
        );
        let hint = "W/S elevation  |  A G P aids  |  V view  |  L trail  |  H in hand  |  R reset  |  Esc menu";
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
        let p = &self.practice;
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
            format!("last hash {}", p.last_hash.map_or("-".into(), hash_hex)),
        ];
        if let Some(pb) = &p.playback {
            let o = pb.outcome();
            lines.push(format!(
                "t {:.3} / {:.3} s, {} events",
                pb.time(),
                o.duration,
                o.events.len()
            ));
        }
        draw::debug_lines(layout, &lines);
    }
}
