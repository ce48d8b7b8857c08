//! The only place that reads the mouse, the keyboard and the touch screen: one [`InputFrame`]
//! per frame.

use macroquad::prelude::{
    get_char_pressed, get_dropped_files, is_key_down, is_key_pressed, is_mouse_button_down,
    is_mouse_button_pressed, is_mouse_button_released, mouse_position, mouse_wheel, touches,
    KeyCode, MouseButton, TouchPhase,
};

use std::sync::atomic::{AtomicBool, Ordering};

use breakshot_client::play::{InputFrame, Key, Tool, TwoFingers};

const KEYS: [(KeyCode, Key); 35] = [
    (KeyCode::Space, Key::Shoot),
    (KeyCode::A, Key::AimLine),
    (KeyCode::G, Key::GhostBall),
    (KeyCode::P, Key::Paths),
    (KeyCode::F3, Key::Debug),
    (KeyCode::H, Key::BallInHand),
    (KeyCode::R, Key::Rerack),
    (KeyCode::Escape, Key::Back),
    (KeyCode::Enter, Key::Shoot),
    (KeyCode::Right, Key::Next),
    (KeyCode::N, Key::Next),
    (KeyCode::Left, Key::Previous),
    (KeyCode::Equal, Key::Faster),
    (KeyCode::KpAdd, Key::Faster),
    (KeyCode::Minus, Key::Slower),
    (KeyCode::KpSubtract, Key::Slower),
    (KeyCode::C, Key::Concede),
    (KeyCode::T, Key::Chat),
    (KeyCode::Backspace, Key::Erase),
    (KeyCode::Enter, Key::Send),
    (KeyCode::Up, Key::PowerUp),
    (KeyCode::Down, Key::PowerDown),
    (KeyCode::K, Key::KeepSpin),
    (KeyCode::V, Key::View),
    (KeyCode::L, Key::Trail),
    (KeyCode::M, Key::Mute),
    (KeyCode::LeftBracket, Key::VolumeDown),
    (KeyCode::RightBracket, Key::VolumeUp),
    (KeyCode::U, Key::Tool(Tool::Undo)),
    (KeyCode::Y, Key::Tool(Tool::Redo)),
    (KeyCode::B, Key::Tool(Tool::Again)),
    (KeyCode::I, Key::Tool(Tool::Advice)),
    (KeyCode::J, Key::Tool(Tool::PlayAdvice)),
    (KeyCode::O, Key::Tool(Tool::SavePosition)),
    (KeyCode::F, Key::Tool(Tool::Arrange)),
];

/// −1, 0 or 1 as one key or the other is held.
fn axis(minus: KeyCode, plus: KeyCode) -> f32 {
    is_key_down(plus) as i32 as f32 - is_key_down(minus) as i32 as f32
}

/// Set when the process is asked to stop (SIGINT, SIGTERM).
static SIGNALLED: AtomicBool = AtomicBool::new(false);

/// Takes over closing the window and SIGINT/SIGTERM, so both end the frame loop instead of
/// the process: the screens are then dropped in order, which closes the network connection
/// (the opponent hears at once that we left) and stops a hosted server cleanly.
pub fn catch_quit() {
    macroquad::prelude::prevent_quit();
    // A page has no signals: closing its tab ends everything at once.
    #[cfg(not(target_arch = "wasm32"))]
    let watcher = std::thread::Builder::new()
        .name("signals".into())
        .spawn(|| {
            let Ok(runtime) = tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
            else {
                return;
            };
            runtime.block_on(async {
                use tokio::signal::unix::{signal, SignalKind};
                let (Ok(mut term), Ok(mut int)) = (
                    signal(SignalKind::terminate()),
                    signal(SignalKind::interrupt()),
                ) else {
                    return;
                };
                for _ in 0..2 {
                    tokio::select! {
                        _ = term.recv() => {}
                        _ = int.recv() => {}
                    }
                    if SIGNALLED.swap(true, Ordering::Relaxed) {
                        // A second signal while closing: stop at once, as without the watcher.
                        std::process::exit(130);
                    }
                }
            });
        });
    // Without the watcher a signal ends the process as before.
    #[cfg(not(target_arch = "wasm32"))]
    drop(watcher);
}

/// Whether the window was closed or the process asked to stop.
pub fn quit_requested() -> bool {
    macroquad::prelude::is_quit_requested() || SIGNALLED.load(Ordering::Relaxed)
}

/// The last finger's place, and the mouse's place when it was there.
type Finger = ([f32; 2], (f32, f32));

/// This frame's input; `typing`: a line of text is being typed, and takes the keys.
pub fn read(dt: f64, typing: bool) -> InputFrame {
    thread_local! {
        static FINGERS: std::cell::RefCell<TwoFingers> = Default::default();
        /// Where the last finger was, and the mouse's place then: a tap moves no mouse,
        /// so the finger's place stands for the mouse until the mouse itself moves.
        static FINGER: std::cell::Cell<Option<Finger>> = Default::default();
        /// The pointer kept while two fingers look at the table (and after, until one
        /// finger or the mouse moves it), and the mouse's place then: the first finger of
        /// a gesture does not also aim.
        static HELD: std::cell::Cell<Option<Finger>> = Default::default();
        /// The pointer given last frame.
        static LAST: std::cell::Cell<[f32; 2]> = Default::default();
    }
    let touches = touches();
    let down: Vec<[f32; 2]> = touches
        .iter()
        .filter(|t| !matches!(t.phase, TouchPhase::Ended | TouchPhase::Cancelled))
        .map(|t| [t.position.x, t.position.y])
        .collect();
    let (fingers, two_down, two_tapped) =
        FINGERS.with_borrow_mut(|f| (f.update(&down), f.active(), f.tapped()));
    let mouse = mouse_position();
    if let Some(t) = touches.first() {
        FINGER.set(Some(([t.position.x, t.position.y], mouse)));
    }
    let (mx, my) = match FINGER.get() {
        Some((finger, then)) if then == mouse => (finger[0], finger[1]),
        _ => {
            FINGER.set(None);
            mouse
        }
    };
    let one_lands = down.len() == 1 && touches.iter().any(|t| t.phase == TouchPhase::Started);
    let held = match HELD.get() {
        _ if two_down => Some((HELD.get().map_or(LAST.get(), |h| h.0), mouse)),
        Some((at, then)) if then == mouse && !one_lands => Some((at, then)),
        _ => None,
    };
    HELD.set(held);
    let (mx, my) = held.map_or((mx, my), |(at, _)| (at[0], at[1]));
    LAST.set([mx, my]);
    let (_, wheel) = mouse_wheel();
    let control = is_key_down(KeyCode::LeftControl) || is_key_down(KeyCode::RightControl);
    let frame = InputFrame {
        mouse: [mx, my],
        // While two fingers look at the table, the first of them does not also aim.
        left_pressed: is_mouse_button_pressed(MouseButton::Left) && !two_down,
        left_down: is_mouse_button_down(MouseButton::Left) && !two_down,
        left_released: is_mouse_button_released(MouseButton::Left) && !two_down,
        right_down: is_mouse_button_down(MouseButton::Right),
        camera: [
            axis(KeyCode::Q, KeyCode::E),
            axis(KeyCode::End, KeyCode::Home),
            axis(KeyCode::X, KeyCode::Z),
        ],
        // Some platforms report 120 per notch, others 1.
        wheel: if wheel.abs() >= 60.0 {
            wheel / 120.0
        } else {
            wheel.signum() * wheel.abs().min(3.0)
        },
        shift: is_key_down(KeyCode::LeftShift) || is_key_down(KeyCode::RightShift),
        left_key: is_key_down(KeyCode::Left),
        right_key: is_key_down(KeyCode::Right),
        up_key: is_key_down(KeyCode::Up),
        down_key: is_key_down(KeyCode::Down),
        raise_key: is_key_down(KeyCode::W) || is_key_down(KeyCode::PageUp),
        lower_key: is_key_down(KeyCode::S) || is_key_down(KeyCode::PageDown),
        // A two-finger tap switches the view, as V does.
        // Ctrl+V pastes, and is not also V (the view).
        pressed: if control && is_key_pressed(KeyCode::V) {
            vec![Key::Paste]
        } else {
            KEYS.iter()
                .filter(|(code, _)| is_key_pressed(*code))
                .map(|&(_, key)| key)
                .chain(two_tapped.then_some(Key::View))
                .collect()
        },
        // The V of a Ctrl+V comes as a letter too on X11: it pasted, it is not typed.
        typed: std::iter::from_fn(get_char_pressed)
            .filter(|&c| !(c.is_control() || control && c.eq_ignore_ascii_case(&'v')))
            .collect(),
        fingers,
        dropped: get_dropped_files()
            .into_iter()
            .filter_map(|f| f.bytes)
            .collect(),
        dt,
    };
    if typing {
        frame.while_typing()
    } else {
        frame
    }
}
