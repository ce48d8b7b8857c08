//! The replay screen: a recorded game, shot by shot.

use breakshot_client::play::{Aim, InputFrame, Key, ReplayViewer};
use breakshot_client::view::hud::Connection;
use breakshot_client::view::{tray, Frame, Layout, Orientations, Playback};
use breakshot_shared::rules::Command;
use macroquad::prelude::*;

use super::draw::BallsShown;
use super::hud::{game_hud, hint_bar, HudInfo};
use super::table_view::TableView;
use super::{draw, panel, trays, Start, Step};

pub struct ReplayScreen {
    viewer: ReplayViewer,
    frame: Frame,
    /// How each ball is turned, for drawing.
    turns: Orientations,
    view: TableView,
}

impl ReplayScreen {
    pub fn new(viewer: ReplayViewer) -> ReplayScreen {
        let frame = Frame::new(viewer.game().table(), viewer.game().balls());
        ReplayScreen {
            viewer,
            frame,
            turns: Orientations::new(),
            view: TableView::new(),
        }
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        for key in &input.pressed {
            match key {
                Key::Shoot => self.viewer.paused = !self.viewer.paused,
                Key::Next => self.viewer.step(),
                Key::Previous => self.viewer.step_back(),
                Key::Faster => self.viewer.faster(),
                Key::Slower => self.viewer.slower(),
                Key::Back => return Step::Open(Start::Menu),
                _ => {}
            }
        }
        self.viewer.tick(input.dt);
        // The camera looks at the cue ball along the shot being shown (or the next one).
        let game = self.viewer.game();
        let (done, _) = self.viewer.position();
        let aim = match self.viewer.record().entries.get(done).map(|e| &e.command) {
            Some(Command::Shot { strike, .. }) => Aim::from_strike(strike).dir(),
            _ => ::glam::DVec2::Y,
        };
        // The ball struck: the shot's while one is shown, else the next shooter's.
        let struck = self.viewer.shot().map_or(game.cue_ball(), Playback::cue);
        let cue = game
            .balls()
            .get(struck)
            .map_or(::glam::DVec2::ZERO, |b| b.pos);
        self.view
            .update(input, cue, aim, self.viewer.shot().is_none());
        Step::Stay
    }

    /// The shot being shown, if any.
    pub fn shot(&self) -> Option<&Playback> {
        self.viewer.shot()
    }

    pub fn draw(&mut self) {
        self.turns.follow(self.viewer.shot());
        let layout = Layout::new(screen_width(), screen_height(), self.frame);
        let v = &self.viewer;
        let r = v.game().params().ball_radius;
        let ids = v.game().ball_ids();
        let pen = self.view.pen(&layout, r, v.shot(), v.game().table());
        draw::table(&pen, v.game().table());
        let states = v.balls();
        let shown = BallsShown {
            ids: &ids,
            states: &states,
            radius: r,
            skip: None,
            turns: &self.turns,
        };
        draw::balls(&pen, &shown);
        let (pocketed, seats) = (v.tray(), tray::seat_names(v.players()));
        let trays = tray::trays(v.game(), &pocketed);
        trays::player_trays(&layout, &ids, trays, &pocketed, seats, r);
        // The panel shows the strike of the shot being played (or the next one).
        let (done, total) = v.position();
        if let Some(Command::Shot { strike, .. }) = v.record().entries.get(done).map(|e| &e.command)
        {
            panel::panel(&layout, &Aim::from_strike(strike), None);
        }

        game_hud(
            &layout,
            &HudInfo {
                game: v.game(),
                me: None,
                verdict: v.last_verdict.as_ref(),
                shot_clock: None,
                connection: &Connection::Offline,
                names: v.players(),
                ratings: &[None, None],
            },
        );
        let state = if v.at_end() && v.shot().is_none() {
            "end"
        } else if v.paused {
            "paused"
        } else {
            "playing"
        };
        let line = format!(
            "Replay: entry {done} of {total}  |  {state}  |  speed x{}  |  Space pause  |  Left/Right shot by shot  |  +/- speed  |  V 3-D view  |  Esc menu",
            v.speed
        );
        hint_bar(&layout, &line, LIGHTGRAY);
        let mut warnings = Vec::new();
        if !v.mismatches.is_empty() {
            warnings.push(format!(
                "hash differs from the record at entries {:?}",
                v.mismatches
            ));
        }
        if let Some(why) = &v.stopped {
            warnings.push(format!("replay stopped: {why}"));
        }
        // On the notice line under the trays, off the cloth and its balls.
        if !warnings.is_empty() {
            let text = warnings.join("  |  ");
            draw::label_in(&text, layout.notice, 20.0, draw::Align::Left, RED);
        }
    }
}
