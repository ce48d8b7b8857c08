//! The game screen: a rules game decided elsewhere (a server, or the rules here for two
//! players at one computer), shown from the events of a [`GameLink`].

use ::glam::DVec2;
use breakshot_client::play::leave::{self, LeaveAnswer};
use breakshot_client::play::{
    next_level, Advice, AdviceOffer, Advisor, Aim, AimShare, AwayResult, Chat, ChatKey, ChatLine,
    Context, Controls, CueMode, Drag, GameEvent, GameFlow, GameLink, History, InputFrame, Intent,
    Key, Prompt, Tool,
};
use breakshot_client::view::aids::{self, AidToggles, Prediction};
use breakshot_client::view::hud::{self, call_prompt, connection as connection_text, Connection};
use breakshot_client::view::snooker as view_snooker;
use breakshot_client::view::{
    choice_at, choice_buttons, tray, Frame, Layout, Orientations, Playback, Rect,
};
use breakshot_shared::ai::Level;
use breakshot_shared::hash::{hash_hex, state_hash};
use breakshot_shared::physics::{Shot, Simulator, Strike, Table};
use breakshot_shared::protocol::limits::RECONNECT_WINDOW;
use breakshot_shared::protocol::{AimAid, Invite};
use breakshot_shared::rules::{
    is_off_table, pocket_name, rack, Command, Game, Phase, Seat, Variant,
};
use macroquad::prelude::*;

use super::draw::BallsShown;
use super::hud::{game_hud, hint_bar, HudInfo};
use super::table_view::TableView;
use super::{draw, invite, panel, snooker, trays, Start, Step};

mod keys;

pub struct GameScreen {
    link: Box<dyn GameLink>,
    flow: GameFlow,
    controls: Controls,
    aim_share: AimShare,
    toggles: AidToggles,
    sim: Simulator,
    /// The shot the aids were computed for, what they show, and the rules' warning for it.
    predicted: Option<(Shot, Prediction, Option<String>)>,
    debug: bool,
    frame_ms: f64,
    /// The last state told to whoever watches a page ([`super::report`]).
    reported: String,
    /// The last line under the table told to whoever watches ("Game resumed", ...).
    reported_message: String,
    /// The last chat line reported (a player's, or a server's notice such as a drain).
    reported_chat: Option<ChatLine>,
    /// The turn line, the last verdict's lines and the players' lines as last reported.
    reported_lines: (String, String, String),
    /// The line under a game's result last reported.
    reported_after: String,
    /// The invite panel's button pressed last.
    copied: Option<invite::Copied>,
    /// How each ball is turned, for drawing.
    turns: Orientations,
    /// The player pressed Esc in an online game and is asked whether to leave.
    leaving: bool,
    /// The player asked for a rematch of the game that is over; the other has not yet.
    rematch_asked: bool,
    /// Why the connection closed has been written to the terminal.
    told_terminal: bool,
    /// Top-down or 3-D, and the 3-D camera.
    view: TableView,
    /// The player's shots to take back, against the computer.
    history: History,
    /// The computer's advice asked for at this computer (not online).
    advice: Option<Asked>,
    /// Whose noise the advice's chance is for: 3 to begin, the next each time I is pressed
    /// on an advice shown.
    advice_level: Level,
    /// The shot played here where advice is offered, until it has played out: the game it
    /// was played on, the seat, the strike and the call.
    awaiting: Option<(Game, Seat, Strike, Option<u8>)>,
    /// The last shot missed (fouled or lost the turn): the game it was played on, its
    /// strike and call, for the advice on it.
    missed: Option<(Game, Strike, Option<u8>)>,
}

/// Advice asked for: the turn it is shown on, the search and, once found, the advice.
struct Asked {
    turn: u32,
    advisor: Advisor,
    found: Option<Advice>,
    /// It compares a miss on the table the miss was played from while the table stays as
    /// it now is (a local game for two): it cannot be played here (J), and I asks about
    /// the table as it stands.
    beside: bool,
}

impl GameScreen {
    /// The players' names by seat, for a game whose link does not say them (the server
    /// does in an online game).
    pub fn with_names(mut self, names: [Option<String>; 2]) -> GameScreen {
        self.flow.names = names;
        self
    }

    pub fn new(link: Box<dyn GameLink>, connection: Connection) -> GameScreen {
        GameScreen {
            link,
            flow: GameFlow::new(connection),
            controls: Controls::new(Aim::default()),
            aim_share: AimShare::default(),
            toggles: AidToggles::default(),
            sim: Simulator::new(),
            predicted: None,
            debug: false,
            frame_ms: 0.0,
            reported: String::new(),
            reported_message: String::new(),
            reported_chat: None,
            reported_lines: Default::default(),
            reported_after: String::new(),
            copied: None,
            turns: Orientations::new(),
            leaving: false,
            rematch_asked: false,
            told_terminal: false,
            view: TableView::new(),
            history: History::new(),
            advice: None,
            advice_level: Level::new(3),
            awaiting: None,
            missed: None,
        }
    }

    fn layout(game: &Game) -> Layout {
        Layout::new(
            screen_width(),
            screen_height(),
            Frame::new(game.table(), game.balls()),
        )
    }

    /// Where the cue ball is, or waits to be placed when it is off the table.
    fn cue_spot(game: &Game) -> DVec2 {
        let cue = game.balls()[game.cue_ball()];
        if is_off_table(&cue) {
            rack::break_spot(game.table())
        } else {
            cue.pos
        }
    }

    /// The invite to show: this computer hosts and the other seat is still empty.
    fn waiting_invite(&self) -> Option<&Invite> {
        self.link
            .invite()
            .filter(|_| self.flow.connection == Connection::WaitingForOpponent)
    }

    /// What the player here may do.
    fn prompt(&self) -> Prompt {
        self.flow
            .prompt_here(self.link.seat(), self.link.watching())
    }

    /// What this game offers of the computer's advice.
    fn advice_offer(&self) -> AdviceOffer {
        AdviceOffer::of(
            self.flow.connection == Connection::Offline,
            self.flow.aim_aid,
            self.link.watching(),
            self.link.takes_back(),
        )
    }

    /// The aids to draw: those toggled on that the room allows.
    fn shown_aids(&self) -> AidToggles {
        self.toggles.allowed_by(self.flow.aim_aid)
    }

    pub fn update(&mut self, input: &InputFrame) -> Step {
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * input.dt * 1000.0;
        while let Some(event) = self.link.poll() {
            self.flow.handle(event);
        }
        if let Some((turn, hash)) = self.flow.take_desync() {
            self.link.report_desync(turn, hash);
        }
        self.report();
        // A rematch asked for is answered by the next game.
        if !self
            .flow
            .game()
            .is_some_and(|g| matches!(g.phase(), Phase::Over { .. }))
        {
            self.rematch_asked = false;
        }
        // Why a connection ended goes to the terminal too: a player who started the game
        // from a command line reads it there.
        if let (Connection::Closed(reason), false) = (&self.flow.connection, self.told_terminal) {
            eprintln!("breakshot: {reason}");
            self.told_terminal = true;
        }
        let mut input = input.clone();
        if let Some(invite) = self.waiting_invite() {
            let area = self
                .flow
                .game()
                .map_or(Rect::new(0.0, 0.0, screen_width(), screen_height()), |g| {
                    Self::layout(g).outer
                });
            let link = self.link.web_link();
            let clicked = input
                .left_pressed
                .then(|| invite::copy_clicked(area, link.is_some(), input.mouse))
                .flatten();
            if let Some(what) = clicked {
                match (what, link) {
                    (invite::Copied::Link, Some(link)) => invite::copy(&link),
                    _ => invite::copy(&invite.to_string()),
                }
                self.copied = Some(what);
                input.left_pressed = false;
            }
        }
        // While a chat line is open, the keyboard types into it and nothing else.
        let chatting = if self.flow.chat.typing().is_some() {
            self.type_chat(&input);
            true
        } else if self.link.chats() && input.pressed.contains(&Key::Chat) {
            self.flow.chat.open();
            true
        } else {
            false
        };
        if !chatting && self.flow.shot().is_some() && input.pressed.contains(&Key::Shoot) {
            self.flow.skip();
            // The key that skipped the shot is spent: it must not also play the next one.
            input.pressed.retain(|k| *k != Key::Shoot);
        }
        let input = &input;
        self.flow.tick(input.dt);
        self.link.update(&self.flow, input.dt);
        if chatting {
            return Step::Stay;
        }
        let Some(game) = self.flow.game().cloned() else {
            // A result screen goes back to the menu on Enter, Space or a click too.
            let done = input.pressed.contains(&Key::Back)
                || (self.flow.ended_away.is_some()
                    && (input.pressed.contains(&Key::Shoot) || input.left_pressed));
            return if done {
                Step::Open(Start::Menu)
            } else {
                Step::Stay
            };
        };
        if self.leaving {
            return self.answer_leave(&game, input);
        }
        let layout = Self::layout(&game);
        let prompt = self.prompt();
        let mut input = input.clone();

        match &prompt {
            Prompt::Decide { seat, options } if input.left_pressed => {
                if let Some(choice) = choice_at(&layout, options, input.mouse) {
                    self.link.send(&game, *seat, Command::Decide(choice));
                }
                input.left_pressed = false;
            }
            Prompt::Shoot { seat, .. } if input.left_pressed => {
                if let Phase::Shooting { options, .. } = game.phase() {
                    if let Some(choice) = choice_at(&layout, options, input.mouse) {
                        self.link.send(&game, *seat, Command::Decide(choice));
                        input.left_pressed = false;
                    }
                }
            }
            _ => {}
        }
        let aiming = matches!(prompt, Prompt::Shoot { .. });
        let r = game.params().ball_radius;
        let aim = self.controls.aim.dir();
        self.view.update(&input, Self::cue_spot(&game), aim, aiming);
        let mut input = self.view.pointer(&input, &layout, r);
        // Snooker: a click on a ball that may be nominated nominates it.
        if let (Prompt::Shoot { seat, .. }, Phase::Shooting { options, .. }) =
            (&prompt, game.phase())
        {
            let at = layout.to_scene(input.mouse);
            let nomination = input
                .left_pressed
                .then(|| view_snooker::nomination_at(&game, *seat, options, at))
                .flatten();
            if let Some(answer) = nomination {
                match answer {
                    Ok(choice) => self.link.send(&game, *seat, Command::Decide(choice)),
                    Err(why) => self.flow.handle(GameEvent::Refused(why)),
                }
                input.left_pressed = false;
            }
        }
        if let Prompt::Shoot { call: true, .. } = prompt {
            if input.left_pressed {
                if let Some(p) = layout.pocket_at(&Table::new(game.table()), input.mouse) {
                    self.flow.call = Some(p);
                    self.flow.message = format!("Called: {}", pocket_name(game.table(), p));
                    input.left_pressed = false;
                }
            }
        }

        let cue_mode = prompt.cue_mode();
        let ctx = Context {
            layout: &layout,
            cue: Self::cue_spot(&game),
            radius: game.params().ball_radius,
            cue_mode,
        };
        let legal = |p: DVec2| game.legal_cue_placement([p.x, p.y]).is_ok();
        let intents = self.controls.update(&input, &ctx, &legal);
        // Online, the others see this player's cue move as they aim.
        if cue_mode != CueMode::Watching && self.link.seat().is_some() {
            if let Some(strike) = self.aim_share.offer(self.controls.aim.strike(), input.dt) {
                self.link.aim(game.turn(), strike);
            }
        }
        let seat = match prompt {
            Prompt::Shoot { seat, .. } | Prompt::Decide { seat, .. } => Some(seat),
            Prompt::Wait => None,
        };
        let offer = self.advice_offer();
        for intent in intents {
            match (intent, seat) {
                (Intent::Shoot(strike), Some(seat)) => {
                    if let Some(cmd) = self.flow.shot_command(strike) {
                        // The rules here say at once what the deciding side would refuse.
                        match game.check(seat, &cmd) {
                            Ok(()) => {
                                if self.link.takes_back() {
                                    self.history.shot(game.clone(), strike);
                                }
                                if offer.allowed() {
                                    let call = match &cmd {
                                        Command::Shot { call, .. } => *call,
                                        _ => None,
                                    };
                                    self.awaiting = Some((game.clone(), seat, strike, call));
                                    self.missed = None;
                                }
                                self.link.send(&game, seat, cmd);
                                self.controls.shot_played();
                            }
                            Err(why) => self.flow.handle(GameEvent::Refused(why.to_string())),
                        }
                    }
                }
                (Intent::PlaceCueBall(pos), Some(seat)) => {
                    self.link.send(&game, seat, Command::PlaceCueBall { pos })
                }
                (Intent::Toggle(aid), _) => self.toggles.toggle(aid),
                (Intent::ToggleDebug, _) => self.debug = !self.debug,
                (Intent::Rerack, _)
                    if matches!(game.phase(), Phase::Over { .. }) && !self.link.watching() =>
                {
                    self.rematch_asked = true;
                    self.history.clear();
                    self.link.rematch()
                }
                // Leaving an online game in play keeps the seat only for a while: ask first.
                (Intent::Back, _)
                    if leave::asks_first(
                        self.link.seat(),
                        &self.flow.connection,
                        matches!(game.phase(), Phase::Over { .. }),
                    ) =>
                {
                    self.leaving = true;
                    return Step::Stay;
                }
                (Intent::Back, _) => return Step::Open(Start::Menu),
                // After a miss: the advice is for the table it was played from, with the
                // chance the shot missed had. Against the computer the shot comes back
                // first; in a game for two the table and the turn stay as they are.
                (Intent::Tool(Tool::Advice), _) if self.missed.is_some() && offer.allowed() => {
                    let Some((before, strike, call)) = self.missed.take() else {
                        continue;
                    };
                    let beside = offer == AdviceOffer::Beside;
                    let turn = if beside {
                        game.turn()
                    } else if let Some(back) = self.take_back(&game, Intent::Tool(Tool::Undo)) {
                        back.turn()
                    } else {
                        return Step::Stay;
                    };
                    let level = self.advice_level;
                    self.advice = Some(Asked {
                        turn,
                        advisor: Advisor::for_game_after_miss(&before, level, strike, call),
                        found: None,
                        beside,
                    });
                    return Step::Stay;
                }
                (Intent::Tool(Tool::Advice), Some(_)) if offer.allowed() => {
                    let shown = self.advice.as_ref().is_some_and(|a| {
                        a.turn == game.turn() && a.found.is_some() && !a.beside
                    });
                    if shown {
                        self.advice_level = next_level(self.advice_level);
                    }
                    let level = self.advice_level;
                    self.advice = Some(Asked {
                        turn: game.turn(),
                        advisor: Advisor::for_game(&game, level),
                        found: None,
                        beside: false,
                    });
                }
                (Intent::Tool(Tool::Advice) | Intent::Tool(Tool::PlayAdvice), _) if !offer.allowed() => {
                    self.flow.message = if self.link.watching() {
                        "No advice: a spectator does not play"
                    } else {
                        "No advice: this room does not allow the computer's advice (hosted without --aids advice)"
                    }
                    .into();
                }
                (Intent::Tool(Tool::PlayAdvice), Some(_)) => match &self.advice {
                    Some(Asked {
                        found: Some(advice),
                        beside: false,
                        ..
                    }) => self.controls.aim = Aim::from_strike(&advice.strike),
                    Some(Asked { beside: true, .. }) => {
                        self.flow.message =
                            "That advice is for the table the miss was played from: I asks about the table now"
                                .into()
                    }
                    _ => {}
                },
                (Intent::Tool(Tool::Undo) | Intent::Tool(Tool::Redo) | Intent::Tool(Tool::Again), _) if self.link.takes_back() => {
                    self.take_back(&game, intent);
                }
                _ => {}
            }
        }
        self.refresh_prediction(&game, cue_mode);
        self.note_miss(&game);
        self.think_advice(&game);
        Step::Stay
    }

    /// Moves the advice's search on a few simulations; says the advice once found. Advice
    /// for an earlier turn is dropped.
    fn think_advice(&mut self, game: &Game) {
        let Some(asked) = &mut self.advice else {
            return;
        };
        if asked.turn != game.turn() {
            self.advice = None;
            return;
        }
        if asked.found.is_some() {
            return;
        }
        let next = if asked.beside {
            "I: advice on the table now"
        } else {
            "J: play it, I: the next level"
        };
        self.flow.message = match asked.advisor.step(6) {
            None => format!(
                "The computer is thinking ({:.0} %)",
                100.0 * asked.advisor.fraction()
            ),
            Some(Ok(advice)) => {
                asked.found = Some(advice.clone());
                if asked.beside {
                    // What a test compares with the miss: the table and the turn kept.
                    super::report(&format!("game advice beside {}", table_state(game)));
                }
                format!("Advice: {}  |  {next}", advice.summary(self.advice_level))
            }
            Some(Err(why)) => format!("No advice: {why}"),
        };
    }

    /// Undo, redo or again against the computer: the table goes back to the replica's own
    /// game before the player's shot (the computer's shots after it go too); the table it
    /// went back to.
    fn take_back(&mut self, game: &Game, intent: Intent) -> Option<Game> {
        let to = match intent {
            Intent::Tool(Tool::Undo) => self.history.undo(game.clone()),
            Intent::Tool(Tool::Redo) => self.history.redo(game.clone()),
            _ => self.history.again(game.clone()),
        };
        let Some(to) = to else {
            self.flow.message = "No shot to take back or play again".into();
            return None;
        };
        // A command the computer sent on the table left behind is stale.
        while self.link.poll().is_some() {}
        let back = to.game.clone();
        self.flow.handle(GameEvent::Started(Box::new(to.game)));
        self.missed = None;
        if let (Intent::Tool(Tool::Again), Some(strike)) = (intent, to.strike) {
            self.controls.aim = Aim::from_strike(&strike);
        }
        self.flow.message = format!(
            "Taken back: {} shots behind, {} ahead  (U undo, Y redo, B again)",
            self.history.behind(),
            self.history.ahead()
        );
        Some(back)
    }

    /// Once the rules have judged the player's own shot against the computer: a foul, or
    /// the turn gone, is a miss the advice can be asked about (I). Judged in the frame the
    /// verdict comes, while the last verdict is still this shot's: the computer's answer
    /// (a choice after a foul) comes a frame later at the soonest.
    fn note_miss(&mut self, game: &Game) {
        if self
            .awaiting
            .as_ref()
            .is_none_or(|(before, ..)| before.turn() == game.turn())
        {
            return;
        }
        let Some((before, seat, strike, call)) = self.awaiting.take() else {
            return;
        };
        let kept = self
            .flow
            .last_verdict
            .as_ref()
            .is_some_and(|v| v.succeeded_for(seat));
        if !kept {
            self.missed = Some((before, strike, call));
            super::report(&format!("game missed {}", table_state(game)));
            self.flow.message = if self.advice_offer() == AdviceOffer::Beside {
                "Missed: I shows what the computer would have played there (the table stays as it is)"
            } else {
                "Missed: I takes the shot back and shows what the computer would have played"
            }
            .into();
        }
    }

    /// Feeds a frame's keys to the open chat line, and sends the line on Enter.
    fn type_chat(&mut self, input: &InputFrame) {
        // Ctrl+V types the clipboard's text (its first line) into the chat line.
        let pasted: Vec<char> = if input.pressed.contains(&Key::Paste) {
            let text = macroquad::miniquad::window::clipboard_get().unwrap_or_default();
            let line = text.lines().next().unwrap_or_default().to_owned();
            line.chars().filter(|c| !c.is_control()).collect()
        } else {
            Vec::new()
        };
        let keys = input
            .typed
            .iter()
            .chain(&pasted)
            .map(|&c| ChatKey::Char(c))
            .chain(input.pressed.iter().filter_map(|k| match k {
                Key::Erase => Some(ChatKey::Erase),
                Key::Send => Some(ChatKey::Send),
                Key::Back => Some(ChatKey::Cancel),
                _ => None,
            }));
        for key in keys.collect::<Vec<_>>() {
            if let Some(text) = self.flow.chat.key(key) {
                super::report(&format!("chat sent {text}"));
                self.link.chat(text);
            }
        }
    }

    /// Esc in an online game asked whether to leave: Esc stays, Enter leaves (the seat is
    /// kept for the reconnect window), C concedes.
    fn answer_leave(&mut self, game: &Game, input: &InputFrame) -> Step {
        let Some(answer) = input.pressed.iter().find_map(|k| leave::answer(*k)) else {
            return Step::Stay;
        };
        self.leaving = false;
        match (answer, self.link.seat()) {
            (LeaveAnswer::Leave, _) => return Step::Open(Start::Menu),
            (LeaveAnswer::Concede, Some(seat)) => self.link.send(game, seat, Command::Concede),
            _ => {}
        }
        Step::Stay
    }

    fn draw_leave_question(&self) {
        let (w, h) = (screen_width(), screen_height());
        let pw = (0.7 * w).clamp(300.0, 760.0);
        let (x, y) = (0.5 * (w - pw), 0.35 * h);
        let lines = leave::question(RECONNECT_WINDOW);
        let mut rows: Vec<(String, f32, Color)> = vec![(lines[0].clone(), 28.0, WHITE)];
        rows.extend(
            invite::wrap(&lines[1], pw - 32.0, 20.0)
                .into_iter()
                .map(|l| (l, 20.0, LIGHTGRAY)),
        );
        rows.push((lines[2].clone(), 20.0, YELLOW));
        let ph = 24.0 + rows.iter().map(|r| 1.5 * r.1).sum::<f32>();
        draw_rectangle(x, y, pw, ph, Color::new(0.0, 0.0, 0.0, 0.85));
        draw_rectangle_lines(x, y, pw, ph, 2.0, WHITE);
        let mut at = y + 12.0;
        for (text, size, c) in rows {
            at += 1.5 * size;
            draw::label(&text, x + 16.0, at - 0.4 * size, size, c);
        }
    }

    fn refresh_prediction(&mut self, game: &Game, cue_mode: CueMode) {
        let cue_off = is_off_table(&game.balls()[game.cue_ball()]);
        if cue_mode == CueMode::Watching || cue_off || !self.shown_aids().any() {
            self.predicted = None;
            return;
        }
        let strike = self.controls.aim.strike();
        let shot = game.shot_for(&strike);
        if self.predicted.as_ref().is_some_and(|(s, ..)| *s == shot) {
            return;
        }
        // The rules judge the shot as it would play; when they cannot yet (a pocket to call
        // first), the physics alone draws the aids.
        let cue = game.cue_ball();
        let (prediction, warning) = match game.preview(game.to_move(), &strike, self.flow.call) {
            Ok(verdict) => (
                verdict
                    .outcome
                    .as_ref()
                    .map(|o| aids::prediction_of(o, cue))
                    .unwrap_or_default(),
                aids::preview_warning(&verdict, game.to_move()),
            ),
            Err(_) => (
                aids::predict(&mut self.sim, &shot, cue).unwrap_or_default(),
                None,
            ),
        };
        self.predicted = Some((shot, prediction, warning));
    }

    /// The shot being shown, if any.
    pub fn shot(&self) -> Option<&Playback> {
        self.flow.shot()
    }

    /// True while a chat line is being typed: it takes the keys.
    pub fn typing(&self) -> bool {
        self.flow.chat.typing().is_some()
    }

    /// True while the server has not answered our entry yet: no game, no result, no
    /// refusal, and the connection not closed. (Being connected is not an answer: the
    /// handshake ends before the server has read our join.)
    pub fn awaiting_server(&self) -> bool {
        self.flow.game().is_none()
            && self.flow.ended_away.is_none()
            && self.flow.message.is_empty()
            && !matches!(self.flow.connection, Connection::Closed(_))
    }

    pub fn draw(&mut self) {
        self.turns.follow(self.flow.shot());
        if let (None, Some(result)) = (self.flow.game(), &self.flow.ended_away) {
            draw_away_result(result);
            return;
        }
        let Some(game) = self.flow.game() else {
            // Before a game, a message is a refusal (no such room, room full).
            let failed = matches!(self.flow.connection, Connection::Closed(_))
                || !self.flow.message.is_empty();
            let headline = if failed {
                "Could not join the game (Esc: menu)"
            } else {
                "Waiting for the game to start..."
            };
            draw::label(headline, 40.0, 80.0, 28.0, WHITE);
            // Long reasons (a fingerprint that does not match, say) wrap inside the window.
            let width = screen_width() - 80.0;
            let state = connection_text(&self.flow.connection);
            let mut y = 120.0;
            for (text, c) in [
                (state.as_str(), LIGHTGRAY),
                (self.flow.message.as_str(), YELLOW),
            ] {
                for line in invite::wrap(text, width, 22.0) {
                    draw::label(&line, 40.0, y, 22.0, c);
                    y += 30.0;
                }
            }
            return;
        };
        let layout = Self::layout(game);
        let r = game.params().ball_radius;
        let balls = self.flow.balls();
        let names = game.ball_ids();
        let prompt = self.prompt();
        let pen = self.view.pen(&layout, r, self.flow.shot(), game.table());
        draw::table(&pen, game.table());

        let dragging = match self.controls.drag {
            Drag::CueBall { at } => Some((at, game.legal_cue_placement([at.x, at.y]).is_ok())),
            _ => None,
        };
        let cue = Self::cue_spot(game);
        if let (Some((_, pred, _)), None) = (&self.predicted, dragging) {
            let object = pred
                .first_hit
                .and_then(|b| names.get(b))
                .map_or("", |s| s.as_str());
            draw::aids(&pen, pred, self.shown_aids(), r, object);
        }
        let shown = BallsShown {
            ids: &names,
            states: &balls,
            radius: r,
            skip: dragging.map(|_| game.cue_ball()),
            turns: &self.turns,
        };
        draw::balls(&pen, &shown);
        let shooting = matches!(prompt, Prompt::Shoot { .. }) && dragging.is_none();
        if shooting {
            // In 9-ball the ball on is ringed.
            if game.variant() == Variant::NineBall {
                for n in game.legal_first_balls() {
                    draw::ring(&pen, balls[usize::from(n)].pos, r, YELLOW);
                }
            }
            snooker::nominated_ring(&pen, game, &balls, r);
            // A shot the rules would judge a foul (or a loss) is warned of in their words.
            if let Some((_, pred, Some(warning))) = &self.predicted {
                if let Some(end) = pred.aim_end.filter(|_| self.shown_aids().aim_line) {
                    draw::segment(&pen, cue, end, 2.5, RED);
                }
                // On the notice line under the trays, off the cloth and its balls (the call
                // prompt, which it never meets, uses it too: without a call there is no
                // preview).
                draw::label_in(warning, layout.notice, 20.0, draw::Align::Left, RED);
            }
        }
        if let Prompt::Shoot {
            in_hand: Some(area),
            ..
        } = &prompt
        {
            let (lo, hi) = game.in_hand_area(*area);
            let (a, b) = (layout.to_screen(lo), layout.to_screen(hi));
            let rect = Rect::new(
                a[0].min(b[0]),
                a[1].min(b[1]),
                (b[0] - a[0]).abs(),
                (b[1] - a[1]).abs(),
            );
            draw::in_hand(&pen, rect, dragging, r);
            if is_off_table(&balls[game.cue_ball()]) && dragging.is_none() {
                draw::ball_at(&pen, "cue", cue, r);
            }
        }
        if let Prompt::Shoot { call: true, .. } = prompt {
            self.draw_call(&pen, game);
        }
        if shooting {
            draw::cue_stick(&pen, cue, &self.controls.aim, r);
        } else if let Some(strike) = self.flow.opponent_aim(self.link.seat()) {
            draw::cue_stick(&pen, cue, &Aim::from_strike(&strike), r);
        }
        let (pocketed, seats) = (self.flow.tray(), tray::seat_names(&self.flow.names));
        // While a shot plays, its balls fall into the trays of the groups as they were when
        // it was struck: a group the shot decides takes its balls once the shot is over.
        let trays = tray::trays(self.flow.shown_game().unwrap_or(game), &pocketed);
        trays::player_trays(&layout, &names, trays, &pocketed, seats, r);
        panel::panel(&layout, &self.controls.aim, Some(self.controls.keep_spin));
        let over = matches!(game.phase(), Phase::Over { .. });
        game_hud(
            &layout,
            &HudInfo {
                game: self.flow.shown_game().unwrap_or(game),
                me: self.link.seat(),
                // Once the game is over, the banner says how it ended where the verdict was.
                verdict: self.flow.shown_verdict().filter(|_| !over),
                shot_clock: self.flow.shown_shot_clock(),
                connection: &self.flow.connection,
                names: &self.flow.names,
                ratings: &self.flow.ratings,
            },
        );
        if self.link.chats() {
            draw_chat(&layout, &self.flow.chat);
        }
        let options = match (&prompt, game.phase()) {
            (Prompt::Decide { options, .. }, _) => options.clone(),
            (Prompt::Shoot { .. }, Phase::Shooting { options, .. }) => options.clone(),
            _ => Vec::new(),
        };
        for (choice, rect) in choice_buttons(&layout, &options) {
            let (text, fill, ink) = if game.snooker().is_some() {
                snooker::button(choice)
            } else {
                (
                    choice.to_string(),
                    Color::from_rgba(30, 60, 120, 220),
                    WHITE,
                )
            };
            draw_rectangle(rect.x, rect.y, rect.w, rect.h, fill);
            draw_rectangle_lines(rect.x, rect.y, rect.w, rect.h, 2.0, WHITE);
            let inside = Rect::new(rect.x + 6.0, rect.y + 2.0, rect.w - 12.0, rect.h - 4.0);
            draw::label_in(&text, inside, 22.0, draw::Align::Centre, ink);
        }
        if let Phase::Over { reason, .. } = game.phase() {
            let names = &self.flow.names;
            let banner = hud::game_over_banner(game, self.link.seat(), names).unwrap_or_default();
            let next = self.after_the_game();
            let lines = [
                (banner, 40.0, YELLOW),
                (hud::named(reason, names), 22.0, WHITE),
                (next, 20.0, LIGHTGRAY),
            ];
            // Under the trays, in the notice's and the verdict's place: the balls stay in view.
            let b = layout.banner;
            draw_rectangle(b.x, b.y, b.w, b.h, Color::new(0.0, 0.0, 0.0, 0.75));
            for ((text, size, c), r) in lines.iter().zip(layout.banner_rows()) {
                draw::label_in(text, r, *size, draw::Align::Centre, *c);
            }
        }
        if self.link.thinking() && !over {
            draw_thinking(&layout);
        }
        let message = self.flow.message.as_str();
        let footer = match (self.link.watching(), message.is_empty()) {
            // A room that allows the players the computer's advice says so to those who
            // watch it too.
            (true, true) => keys::watcher_keys(self.flow.aim_aid == AimAid::Advice),
            (true, false) => format!("Watching  |  {message}"),
            (false, true) => keys::player_keys(
                self.link.chats(),
                self.advice_offer(),
                self.link.takes_back(),
            ),
            (false, false) => message.to_string(),
        };
        hint_bar(&layout, &footer, LIGHTGRAY);
        if self.debug {
            self.debug_overlay(&layout, game);
        }
        if let Some(invite) = self.waiting_invite() {
            invite::draw_panel(
                layout.outer,
                invite,
                self.link.web_link().as_deref(),
                self.copied,
            );
        }
        if self.leaving {
            self.draw_leave_question();
        }
    }

    /// The pockets to call, the called one marked.
    fn draw_call(&self, pen: &draw::Pen, game: &Game) {
        let layout = pen.layout;
        let table = Table::new(game.table());
        for (i, pk) in table.pockets.iter().enumerate() {
            let centre = table.to_scene(pk.center);
            let chosen = self.flow.call == Some(i as u8);
            let c = if chosen {
                YELLOW
            } else {
                Color::new(1.0, 1.0, 1.0, 0.5)
            };
            draw::mark(pen, centre, pk.radius, if chosen { 4.0 } else { 2.0 }, c);
        }
        if self.flow.call.is_none() {
            let notice = layout.notice;
            draw::label_in(call_prompt(game), notice, 22.0, draw::Align::Left, YELLOW);
        }
    }

    /// The line under the result of a game that is over: how to go on, or whom a rematch
    /// asked for waits for.
    fn after_the_game(&self) -> String {
        let asked = self.rematch_asked && self.flow.connection != Connection::Offline;
        hud::after_the_game(
            self.link.watching(),
            asked,
            self.link.seat(),
            &self.flow.names,
        )
    }

    /// Tells whoever watches the page (its tests) how the game stands, when that changed: the
    /// seat, the shots confirmed by the server's hash and the desyncs, and the end; and the
    /// line under the table, the one under a game's result, the turn line and the verdict
    /// when they change.
    fn report(&mut self) {
        if !super::reporting() {
            return;
        }
        let replica = self.flow.replica();
        let over = match self.flow.game().map(Game::phase) {
            Some(Phase::Over { .. }) => "over",
            Some(_) => "playing",
            None => "waiting",
        };
        let line = format!(
            "game {over} seat={} confirmed={} desyncs={} connection={} turn={}",
            self.link
                .seat()
                .map_or("-".to_owned(), |s| format!("{s:?}")),
            replica.confirmed(),
            replica.desyncs(),
            // The kind only: a countdown in it would make a new line every frame.
            self.flow.connection.kind(),
            match self.prompt() {
                Prompt::Wait => "theirs",
                Prompt::Shoot { .. } | Prompt::Decide { .. } => "mine",
            },
        );
        if line != self.reported {
            super::report(&line);
            self.reported = line;
        }
        let after = if over == "over" {
            self.after_the_game()
        } else {
            String::new()
        };
        if after != self.reported_after {
            if !after.is_empty() {
                super::report(&format!("after the game {after}"));
            }
            self.reported_after = after;
        }
        if self.flow.message != self.reported_message {
            self.reported_message = self.flow.message.clone();
            super::report(&format!("message {}", self.reported_message));
        }
        let heard = self.flow.chat.lines().last();
        if heard != self.reported_chat.as_ref() {
            self.reported_chat = heard.cloned();
            if let Some(line) = &self.reported_chat {
                super::report(&format!("chat heard {}", line.shown()));
            }
        }
        // The turn line over the table and the verdict's lines under it, as the HUD words
        // them (with the players' names).
        if let Some(game) = self.flow.shown_game().or(self.flow.game()) {
            let status = hud::status(game, &self.flow.names);
            let verdict = self
                .flow
                .shown_verdict()
                .map(|v| hud::verdict_lines(v, &self.flow.names).join(" / "))
                .unwrap_or_default();
            // The players' lines of the HUD: names, seats, ratings in a rated room.
            let players =
                hud::players(game, self.link.seat(), &self.flow.names, &self.flow.ratings)
                    .map(|p| p.text)
                    .join(" | ");
            if status != self.reported_lines.0 {
                super::report(&format!("status {status}"));
            }
            if verdict != self.reported_lines.1 && !verdict.is_empty() {
                super::report(&format!("verdict {verdict}"));
            }
            if players != self.reported_lines.2 {
                super::report(&format!("players {players}"));
            }
            self.reported_lines = (status, verdict, players);
        }
    }

    fn debug_overlay(&self, layout: &Layout, game: &Game) {
        let mut lines = vec![
            format!("frame {:.1} ms", self.frame_ms),
            format!(
                "turn {}, shots {}",
                game.turn(),
                self.flow.replica().shots()
            ),
            format!("desyncs {}", self.flow.replica().desyncs()),
        ];
        let last_shot = self
            .flow
            .last_verdict
            .as_ref()
            .and_then(|v| v.shot.as_ref());
        if let Some(hash) = last_shot.map(|s| s.hash) {
            lines.push(format!("last hash {}", hash_hex(hash)));
        }
        lines.extend(self.flow.shot().map(draw::debug_shot_line));
        draw::debug_lines(layout, &lines);
    }
}

/// "turn=N table=HASH": the turn and the table's hash, as reports give them.
fn table_state(game: &Game) -> String {
    format!(
        "turn={} table={}",
        game.turn(),
        hash_hex(state_hash(game.balls()))
    )
}

/// The result of a game that ended while this player was away, in the middle of the window.
fn draw_away_result(result: &AwayResult) {
    let (w, h) = (screen_width(), screen_height());
    let [headline, why] = result.lines();
    let color = match result.won {
        Some(true) => GOLD,
        Some(false) => LIGHTGRAY,
        None => WHITE,
    };
    let centred = |text: &str, y: f32, size: f32, c: Color| {
        let x = 0.5 * (w - draw::text_width(text, size));
        draw::label(text, x.max(16.0), y, size, c);
    };
    centred(&headline, 0.4 * h, 48.0, color);
    for (i, line) in invite::wrap(&why, 0.9 * w, 22.0).iter().enumerate() {
        centred(line, 0.4 * h + 50.0 + 30.0 * i as f32, 22.0, LIGHTGRAY);
    }
    centred("Enter or Esc: back to the menu", 0.75 * h, 20.0, YELLOW);
}

/// The chat in its box beside the verdict, off the table: the last lines said that fit,
/// and the line being typed (T opens it, Enter sends, Esc closes).
fn draw_chat(layout: &Layout, chat: &Chat) {
    let mut rows: Vec<(String, Color)> = chat.shown().map(|l| (l.shown(), WHITE)).collect();
    if let Some(typing) = chat.typing() {
        rows.push((format!("say: {typing}_"), YELLOW));
    }
    if rows.is_empty() {
        return;
    }
    let boxes = layout.chat_rows();
    let shown = &rows[rows.len().saturating_sub(boxes.len())..];
    let c = layout.chat;
    draw_rectangle(c.x, c.y, c.w, c.h, Color::new(0.0, 0.0, 0.0, 0.55));
    // The newest line in the bottom row, the older ones over it.
    for ((text, color), r) in shown.iter().zip(&boxes[boxes.len() - shown.len()..]) {
        let inside = Rect::new(r.x + 6.0, r.y, r.w - 12.0, r.h);
        draw::label_in(text, inside, 18.0, draw::Align::Left, *color);
    }
}

/// "Computer is thinking", on the notice line under the trays (off the cloth, so the rack
/// stays in view), its dots counting the time.
fn draw_thinking(layout: &Layout) {
    let dots = ".".repeat(1 + (get_time() * 3.0) as usize % 3);
    let text = format!("Computer is thinking{dots}");
    draw::label_in(&text, layout.notice, 22.0, draw::Align::Left, WHITE);
}
