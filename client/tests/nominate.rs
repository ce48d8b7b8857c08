//! A person nominates a colour in a real snooker window: two players at one computer play a
//! 6-red frame until a red is potted, every stroke made with the mouse and the keys as a
//! person makes it (the cue ball dragged into the D, the power bar clicked, the cue pointed
//! with the mouse, Space); then, on a colour, a click on the blue nominates it, the black's
//! button in the row over the trays nominates the black, and a click on a red nominates
//! nothing and says why; last a foul and a miss offers the other player its choices as
//! buttons, and a click on "replace the balls" puts them back. The window runs under a virtual display of its own (Xvfb), driven
//! with `xdotool`, photographed with ImageMagick's `import`, and says what it shows in its
//! `report:` lines. The strokes are found here by the same rules and physics the window
//! plays them with, from the very pixels clicked.
//!
//! Without Xvfb, xdotool or ImageMagick the test says why and passes (CI installs them).

use std::process::Command;
use std::time::{Duration, Instant};

use breakshot_client::play::Aim;
use breakshot_client::view::palette::snooker_ball_colour;
use breakshot_client::view::snooker::button_text;
use breakshot_client::view::{choice_buttons, Frame, Layout, Rect};
use breakshot_shared::physics::{Table, TableKind};
use breakshot_shared::rules::snooker::table::{self, BLACK, BLUE};
use breakshot_shared::rules::{
    is_off_table, rack, Choice, Command as Rules, Game, Phase, Settings, Variant,
};
use glam::DVec2;

#[allow(dead_code)]
mod common;
// The window tests' display; not every part of it is used here.
#[allow(dead_code, unused_imports)]
#[path = "friends/display.rs"]
mod display;

use common::reported::Reported;
use display::{shaded, Display, Picture};

const BREAKSHOT: &str = env!("CARGO_BIN_EXE_breakshot");
const SIZE: (u32, u32) = (1280, 720);
/// The rack's seed: the strokes below are searched from it, so any seed would do.
const SEED: u64 = 5;
/// The most strokes played looking for a red potted.
const STROKES: usize = 6;
const PATIENCE: Duration = Duration::from_secs(90);

/// A stroke as a person makes it in the window: the power bar clicked at `power`, the mouse
/// rested at `aim` (the cue points at it), then Space.
#[derive(Clone, Copy, Debug)]
struct Stroke {
    power: [f32; 2],
    aim: [f32; 2],
}

impl Stroke {
    /// The rules' command the window makes of this stroke from a cue ball at `cue`: the
    /// window's own aim, fed the same pixels.
    fn command(&self, layout: &Layout, cue: DVec2) -> Rules {
        let mut aim = Aim::default();
        let bar = layout.power_bar;
        aim.set_power(((bar.y + bar.h - self.power[1]) / bar.h) as f64);
        aim.point_along(layout.to_scene(self.aim) - cue);
        Rules::Shot {
            strike: aim.strike(),
            call: None,
        }
    }
}

fn layout(game: &Game) -> Layout {
    Layout::new(
        SIZE.0 as f32,
        SIZE.1 as f32,
        Frame::new(game.table(), game.balls()),
    )
}

fn pixel(p: [f32; 2]) -> [f32; 2] {
    [p[0].round(), p[1].round()]
}

/// Three places on the power bar to click: a third of its height and more.
fn powers(layout: &Layout) -> [[f32; 2]; 3] {
    let bar = layout.power_bar;
    [0.35f32, 0.5, 0.7].map(|f| pixel([bar.x + 0.5 * bar.w, bar.y + (1.0 - f) * bar.h]))
}

/// The strokes worth trying from `game`: at each red on the table, towards each pocket
/// (through the ghost ball), a pixel or so either side, at three powers.
fn candidates(game: &Game) -> Vec<Stroke> {
    let layout = layout(game);
    let r = game.params().ball_radius;
    let cue = game.balls()[0].pos;
    let table = Table::new(game.table());
    let pockets: Vec<DVec2> = table
        .pockets
        .iter()
        .map(|p| table.to_scene(p.center))
        .collect();
    let powers = powers(&layout);
    let (w, l) = game.table().size().expect("the snooker table's size");
    let (lo, hi) = (DVec2::splat(2.0 * r), DVec2::new(w, l) - 2.0 * r);
    let mut out = Vec::new();
    for red in (1..=table::LAST_RED).filter(|&b| !game.balls()[usize::from(b)].motion.is_gone()) {
        let at = game.balls()[usize::from(red)].pos;
        for pocket in &pockets {
            let ghost = at - 2.0 * r * (*pocket - at).normalize();
            let dir = (ghost - cue).normalize();
            // Too thin a cut, or away from the pocket: not worth a stroke.
            if dir.dot((*pocket - at).normalize()) < 0.6 {
                continue;
            }
            // The mouse rests far along the line, so that a pixel turns the cue little.
            let mut far = ghost;
            while (far + 0.05 * dir).clamp(lo, hi) == far + 0.05 * dir {
                far += 0.05 * dir;
            }
            let centre = pixel(layout.to_screen(far));
            for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
                for power in powers {
                    out.push(Stroke {
                        power,
                        aim: [centre[0] + dx, centre[1] + dy],
                    });
                }
            }
        }
    }
    out
}

/// What `stroke` leaves: the game after it, played here as the window plays it.
fn played(game: &Game, stroke: &Stroke) -> Option<Game> {
    let mut after = game.clone();
    let seat = game.to_move();
    let command = stroke.command(&layout(game), game.balls()[0].pos);
    after.apply(seat, &command).ok()?;
    Some(after)
}

/// Whether `game` has the player on a colour, with none nominated yet.
fn on_a_colour(game: &Game) -> bool {
    let m = game.snooker().expect("snooker");
    matches!(game.phase(), Phase::Shooting { .. }) && m.on_colour && m.nominated.is_none()
}

/// Whether `game` waits for a stroke with no foul to answer first.
fn shooting(game: &Game) -> bool {
    matches!(game.phase(), Phase::Shooting { in_hand: None, .. })
}

/// The stroke to play from `game`: one that pots a red without a foul, else one that leaves
/// the next player simply to shoot (the reds spread for them).
fn next_stroke(game: &Game) -> (Stroke, Game) {
    let tried: Vec<(Stroke, Game)> = candidates(game)
        .into_iter()
        .filter_map(|s| played(game, &s).map(|g| (s, g)))
        .collect();
    tried
        .iter()
        .find(|(_, g)| on_a_colour(g))
        .or_else(|| tried.iter().find(|(_, g)| shooting(g)))
        .cloned()
        .expect("a stroke with no foul")
}

/// Plays `stroke` in window `wid`.
fn play(display: &Display, wid: &str, stroke: &Stroke) {
    click(display, wid, stroke.power);
    point(display, wid, stroke.aim);
    display.xdotool(&["key", "space"]);
}

/// Clicks window `wid` at `at` (its pixels).
fn click(display: &Display, wid: &str, at: [f32; 2]) {
    point(display, wid, at);
    display.xdotool(&["click", "1"]);
}

/// Rests the mouse on window `wid` at `at`, and lets the window see it there.
fn point(display: &Display, wid: &str, at: [f32; 2]) {
    let (x, y) = (at[0].to_string(), at[1].to_string());
    display.xdotool(&["mousemove", "--window", wid, &x, &y]);
    std::thread::sleep(Duration::from_millis(300));
}

/// Whether a pixel is the yellow of the ring round the nominated ball.
fn ring_yellow(p: [u8; 3]) -> bool {
    p[0] > 200 && p[1] > 200 && p[2] < 90
}

/// How many of twelve points round `ball`, where the ring round a nominated ball is drawn,
/// are yellow in `pic`.
fn ringed(pic: &Picture, game: &Game, ball: u8) -> usize {
    let layout = layout(game);
    let [x, y] = layout.to_screen(game.balls()[usize::from(ball)].pos);
    let reach = layout.px(game.params().ball_radius) + 4.0;
    (0..12)
        .map(|k| k as f32 * std::f32::consts::TAU / 12.0)
        .filter(|a| pic.near(x + reach * a.cos(), y + reach * a.sin(), 1, ring_yellow))
        .count()
}

#[test]
fn a_colour_is_nominated_by_a_click_on_the_ball_or_on_its_button_and_a_red_is_refused() {
    let Some(display) = Display::start() else {
        return;
    };
    let dir = breakshot_testkit::scratch("nominate");
    let (w, h) = SIZE;
    let mut command = Command::new(BREAKSHOT);
    display
        .on(&mut command)
        .args(["local", "--mode", "snooker", "--reds", "6", "--seed"])
        .arg(SEED.to_string())
        .args(["--view", "top", "--size", &format!("{w}x{h}"), "--data"])
        .arg(dir.path().join("data"));
    let window = Reported::start(&mut command);
    let wid = display.new_window(&[]);
    window.wait_for(0, PATIENCE, "the frame", |l| l.starts_with("game playing"));
    let mut game = Game::new(
        Variant::Snooker {
            reds: 6,
            best_of: 1,
        },
        Settings::offline(),
        SEED,
    );
    // What the window shows once it shows what `want` looks for: the report of a change
    // comes from the frame's update, its picture a moment later.
    let shown = |name: &str, what: &str, want: &dyn Fn(&Picture) -> bool| {
        let deadline = Instant::now() + PATIENCE;
        loop {
            let pic = display.grab(&wid, &dir.path().join(format!("{name}.png")));
            if want(&pic) {
                return pic;
            }
            assert!(
                Instant::now() < deadline,
                "{what}: not shown within {PATIENCE:?}"
            );
            std::thread::sleep(Duration::from_millis(300));
        }
    };

    // The cue ball, in hand, is dragged from where it waits into the D.
    let screen = layout(&game);
    // Where the window shows it waiting (as `ui/game.rs` puts it).
    let cue = game.balls()[0];
    let waits = if is_off_table(&cue) {
        rack::break_spot(TableKind::Snooker)
    } else {
        cue.pos
    };
    let from = pixel(screen.to_screen(waits));
    let to = pixel(screen.to_screen(table::d_centre() + DVec2::new(0.12, -0.15)));
    point(&display, &wid, from);
    display.xdotool(&["mousedown", "1"]);
    std::thread::sleep(Duration::from_millis(300));
    point(&display, &wid, to);
    display.xdotool(&["mouseup", "1"]);
    let at = screen.to_scene(to);
    game.apply(game.to_move(), &Rules::PlaceCueBall { pos: [at.x, at.y] })
        .expect("the cue ball goes in the D");
    let (_, placed) = window.wait_for(0, PATIENCE, "the cue ball placed", |l| {
        l.starts_with("verdict") && l.contains("places the cue ball")
    });
    eprintln!("{placed}");

    // Strokes until a red is potted, each found here and played in the window.
    for k in 0.. {
        assert!(k < STROKES, "no red potted in {STROKES} strokes");
        let (stroke, after) = next_stroke(&game);
        play(&display, &wid, &stroke);
        game = after;
        let want = hud_status(&game);
        window.wait_for(0, PATIENCE, &format!("stroke {k}: {want}"), |l| {
            l == format!("status {want}")
        });
        if on_a_colour(&game) {
            break;
        }
    }
    shown("on-a-colour", "no ring before a nomination", &|p| {
        ringed(p, &game, BLUE) == 0
    });
    assert!(
        hud_status(&game).contains("on: a colour (nominate one)"),
        "{}",
        hud_status(&game)
    );

    // A click on the blue nominates it: the status says so and the blue is ringed.
    let seat = game.to_move();
    let screen = layout(&game);
    click(
        &display,
        &wid,
        pixel(screen.to_screen(game.balls()[usize::from(BLUE)].pos)),
    );
    game.apply(seat, &Rules::Decide(Choice::Nominate(BLUE)))
        .expect("the blue nominated");
    window.wait_for(0, PATIENCE, "the blue nominated", |l| {
        l.starts_with("status") && l.contains("on: the blue (nominated)")
    });
    let blue = shown("blue", "the blue ringed", &|p| ringed(p, &game, BLUE) >= 9);

    // The black's button, in the black, over the trays, nominates the black instead.
    let Phase::Shooting { options, .. } = game.phase().clone() else {
        panic!("not shooting: {:?}", game.phase());
    };
    let (_, black) = *choice_buttons(&screen, &options)
        .iter()
        .find(|(c, _)| *c == Choice::Nominate(BLACK))
        .expect("a button for the black");
    assert_eq!(button_text(Choice::Nominate(BLACK)), "black");
    let middle = |r: Rect| [r.x + 0.5 * r.w, r.y + 0.5 * r.h];
    let fill = blue.at(black.x + 4.0, black.y + 0.5 * black.h);
    assert!(
        shaded(fill, snooker_ball_colour(BLACK), 12.0),
        "the black's button is {fill:?}"
    );
    click(&display, &wid, middle(black));
    game.apply(seat, &Rules::Decide(Choice::Nominate(BLACK)))
        .expect("the black nominated");
    window.wait_for(0, PATIENCE, "the black nominated", |l| {
        l.starts_with("status") && l.contains("on: the black (nominated)")
    });
    shown("black", "the black ringed, not the blue", &|p| {
        ringed(p, &game, BLACK) >= 9 && ringed(p, &game, BLUE) == 0
    });

    // A click on a red nominates nothing: the rules' reason is shown, the black stays.
    let red = (1..=table::LAST_RED)
        .find(|&b| !game.balls()[usize::from(b)].motion.is_gone())
        .expect("a red on the table");
    let heard = window.said().len();
    click(
        &display,
        &wid,
        pixel(screen.to_screen(game.balls()[usize::from(red)].pos)),
    );
    let (_, why) = window.wait_for(heard, PATIENCE, "the red refused", |l| {
        l.starts_with("message Refused")
    });
    assert!(why.contains("a red is not a colour"), "{why}");
    std::thread::sleep(Duration::from_secs(1));
    let said = window.said();
    assert!(
        !said[heard..].iter().any(|l| l.starts_with("status")),
        "the red changed the status: {:?}",
        &said[heard..]
    );
    shown("red", "the black still ringed", &|p| {
        ringed(p, &game, BLACK) >= 9
    });

    // A foul and a miss (the red hit first, the black on): the other player is offered the
    // choices as buttons over the trays, and a click on "replace the balls" puts them back
    // for the offender to play again.
    let foul = Stroke {
        power: powers(&screen)[1],
        aim: pixel(screen.to_screen(game.balls()[usize::from(red)].pos)),
    };
    let before = game.clone();
    game = played(&game, &foul).expect("the foul is a stroke the rules take");
    let Phase::Deciding { options } = game.phase().clone() else {
        panic!("no choice after the foul: {:?}", game.phase());
    };
    assert!(options.contains(&Choice::ReplaceBalls), "{options:?}");
    play(&display, &wid, &foul);
    let want = hud_status(&game);
    window.wait_for(0, PATIENCE, &format!("the foul: {want}"), |l| {
        l == format!("status {want}")
    });
    let screen = layout(&game);
    let buttons = choice_buttons(&screen, &options);
    let (_, replace) = *buttons
        .iter()
        .find(|(c, _)| *c == Choice::ReplaceBalls)
        .expect("a button to replace the balls");
    shown("choices", "the choices' buttons", &|p| {
        buttons
            .iter()
            .all(|(_, r)| shaded(p.at(r.x + 3.0, r.y + 0.5 * r.h), [30, 60, 120], 30.0))
    });
    click(&display, &wid, middle(replace));
    game.apply(game.to_move(), &Rules::Decide(Choice::ReplaceBalls))
        .expect("the balls replaced");
    assert_eq!(game.balls(), before.balls(), "the balls are not back");
    let want = hud_status(&game);
    window.wait_for(0, PATIENCE, &format!("the balls replaced: {want}"), |l| {
        l == format!("status {want}")
    });
    assert!(want.starts_with(&format!("{seat} to shoot")), "{want}");
    drop(window);
}

/// The HUD's status line for `game` (the players unnamed, as at one computer).
fn hud_status(game: &Game) -> String {
    breakshot_client::view::hud::status(game, &[None, None])
}
