//! Chat in an online game: the line being typed, and the last lines said in the room.

use std::collections::VecDeque;

use breakshot_shared::protocol::limits::MAX_CHAT_CHARS;

/// Lines of chat kept on screen.
pub(crate) const SHOWN_LINES: usize = 5;
/// Seconds a line stays on screen while no line is being typed.
pub(crate) const SHOWN_SECS: f64 = 12.0;

/// One line said in the room.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChatLine {
    /// Who said it; empty for the server's own notices.
    pub from: String,
    /// What was said.
    pub text: String,
}

impl ChatLine {
    /// The line as shown: "name: text", or the notice alone.
    pub fn shown(&self) -> String {
        if self.from.is_empty() {
            self.text.clone()
        } else {
            format!("{}: {}", self.from, self.text)
        }
    }
}

/// What the player does to the line being typed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChatKey {
    /// A printable character typed.
    Char(char),
    /// Remove the last character.
    Erase,
    /// Send the line.
    Send,
    /// Close the line without sending it.
    Cancel,
}

/// The chat of one game screen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chat {
    typing: Option<String>,
    /// The last lines, oldest first, with how long ago each was said (seconds).
    lines: VecDeque<(ChatLine, f64)>,
}

impl Chat {
    /// Opens the line to type into (keeping what was typed, if it is open).
    pub fn open(&mut self) {
        self.typing.get_or_insert_with(String::new);
    }

    /// The line being typed, while it is open.
    pub fn typing(&self) -> Option<&str> {
        self.typing.as_deref()
    }

    /// Applies a key to the open line; returns the text to send when the line is sent and
    /// is not blank. Typing stops at the protocol's limit, so what is sent is never refused
    /// for its length.
    pub fn key(&mut self, key: ChatKey) -> Option<String> {
        let line = self.typing.as_mut()?;
        match key {
            ChatKey::Char(c) if !c.is_control() && line.chars().count() < MAX_CHAT_CHARS => {
                line.push(c);
            }
            ChatKey::Char(_) => {}
            ChatKey::Erase => {
                line.pop();
            }
            ChatKey::Cancel => self.typing = None,
            ChatKey::Send => {
                let text = self.typing.take().unwrap_or_default();
                let text = text.trim();
                return (!text.is_empty()).then(|| text.to_owned());
            }
        }
        None
    }

    /// Keeps a line said in the room (the oldest goes past `SHOWN_LINES`).
    pub fn heard(&mut self, from: &str, text: &str) {
        let line = ChatLine {
            from: from.to_owned(),
            text: text.to_owned(),
        };
        self.lines.push_back((line, 0.0));
        while self.lines.len() > SHOWN_LINES {
            self.lines.pop_front();
        }
    }

    /// The last lines said, oldest first.
    pub fn lines(&self) -> impl Iterator<Item = &ChatLine> {
        self.lines.iter().map(|(line, _)| line)
    }

    /// The lines to show now: all of them while a line is typed, else those said in the
    /// last `SHOWN_SECS`.
    pub fn shown(&self) -> impl Iterator<Item = &ChatLine> {
        let all = self.typing.is_some();
        self.lines
            .iter()
            .filter(move |(_, age)| all || *age < SHOWN_SECS)
            .map(|(line, _)| line)
    }

    /// Lets `dt` seconds pass.
    pub fn tick(&mut self, dt: f64) {
        for (_, age) in &mut self.lines {
            *age += dt;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn type_in(chat: &mut Chat, text: &str) {
        for c in text.chars() {
            assert_eq!(chat.key(ChatKey::Char(c)), None);
        }
    }

    #[test]
    fn a_typed_line_is_sent_trimmed_and_the_line_closes() {
        let mut chat = Chat::default();
        assert_eq!(
            chat.key(ChatKey::Char('x')),
            None,
            "closed: keys do nothing"
        );
        chat.open();
        type_in(&mut chat, " nice shot!x");
        chat.key(ChatKey::Erase);
        assert_eq!(chat.typing(), Some(" nice shot!"));
        assert_eq!(chat.key(ChatKey::Send).as_deref(), Some("nice shot!"));
        assert_eq!(chat.typing(), None);
    }

    #[test]
    fn blank_or_cancelled_lines_send_nothing_and_control_characters_are_not_typed() {
        let mut chat = Chat::default();
        chat.open();
        type_in(&mut chat, "  \u{7}");
        assert_eq!(chat.typing(), Some("  "));
        assert_eq!(chat.key(ChatKey::Send), None);
        chat.open();
        type_in(&mut chat, "gg");
        assert_eq!(chat.key(ChatKey::Cancel), None);
        assert_eq!(chat.typing(), None);
    }

    #[test]
    fn typing_stops_at_the_protocols_limit() {
        let mut chat = Chat::default();
        chat.open();
        type_in(&mut chat, &"a".repeat(MAX_CHAT_CHARS + 10));
        assert_eq!(
            chat.typing().map(|t| t.chars().count()),
            Some(MAX_CHAT_CHARS)
        );
    }

    #[test]
    fn only_the_last_lines_are_kept() {
        let mut chat = Chat::default();
        for n in 0..SHOWN_LINES + 2 {
            chat.heard("ann", &n.to_string());
        }
        chat.heard("", "the game reached its length limit");
        let shown: Vec<String> = chat.lines().map(ChatLine::shown).collect();
        assert_eq!(shown.len(), SHOWN_LINES);
        assert_eq!(shown[0], "ann: 3");
        assert_eq!(shown[SHOWN_LINES - 1], "the game reached its length limit");
    }

    #[test]
    fn lines_fade_after_a_while_but_show_again_while_typing() {
        let mut chat = Chat::default();
        chat.heard("ann", "hi");
        chat.tick(SHOWN_SECS / 2.0);
        chat.heard("ben", "hello");
        assert_eq!(chat.shown().count(), 2);
        chat.tick(SHOWN_SECS / 2.0 + 0.1);
        let shown: Vec<String> = chat.shown().map(ChatLine::shown).collect();
        assert_eq!(shown, ["ben: hello"]);
        chat.open();
        assert_eq!(chat.shown().count(), 2);
    }
}
