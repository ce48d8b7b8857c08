//! Where the buttons of the choices a game offers go (push out, play on, a colour to
//! nominate, ...), and which one a click picks.

use breakshot_shared::rules::Choice;

use super::{Layout, Rect};

/// The buttons of the choices offered, in a row over the trays: off the cloth, so they
/// cover no ball and no warning written on it.
pub fn choice_buttons(layout: &Layout, options: &[Choice]) -> Vec<(Choice, Rect)> {
    let n = options.len().max(1) as f32;
    let area = layout.tray;
    let gap = 8.0;
    let w = ((area.w - (n + 1.0) * gap) / n).min(300.0);
    let h = (area.h - 2.0 * gap).clamp(18.0, 44.0);
    let x0 = area.x + 0.5 * (area.w - n * w - (n - 1.0) * gap);
    let y = area.y + 0.5 * (area.h - h);
    options
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let x = x0 + k as f32 * (w + gap);
            (c, Rect::new(x, y, w, h))
        })
        .collect()
}

/// The choice whose button is under `mouse`, if any.
pub fn choice_at(layout: &Layout, options: &[Choice], mouse: [f32; 2]) -> Option<Choice> {
    choice_buttons(layout, options)
        .into_iter()
        .find(|(_, r)| r.contains(mouse))
        .map(|(choice, _)| choice)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::Frame;
    use breakshot_shared::rules::Game;

    fn layout() -> Layout {
        let game = Game::new(
            breakshot_shared::rules::Variant::NineBall,
            breakshot_shared::rules::Settings::offline(),
            1,
        );
        Layout::new(1280.0, 720.0, Frame::new(game.table(), game.balls()))
    }

    #[test]
    fn each_choice_is_a_button_in_a_row_over_the_trays_and_a_click_picks_it() {
        let layout = layout();
        let options = [Choice::PushOut, Choice::AcceptTable];
        let buttons = choice_buttons(&layout, &options);
        assert_eq!(buttons.len(), 2);
        for (_, r) in &buttons {
            assert!(layout.tray.holds(r), "{r:?} not over the trays");
            assert!(!r.overlaps(&layout.outer), "{r:?} over the table");
            assert_eq!(r.y, buttons[0].1.y, "not in one row");
        }
        assert!(
            buttons[0].1.x + buttons[0].1.w < buttons[1].1.x,
            "they overlap"
        );
        let middle = |r: &Rect| [r.x + 0.5 * r.w, r.y + 0.5 * r.h];
        for (choice, r) in &buttons {
            assert_eq!(choice_at(&layout, &options, middle(r)), Some(*choice));
        }
        let below = [
            middle(&buttons[0].1)[0],
            buttons[0].1.y + 2.0 * buttons[0].1.h,
        ];
        assert_eq!(choice_at(&layout, &options, below), None);
        assert_eq!(choice_at(&layout, &[], middle(&buttons[0].1)), None);
    }
}
