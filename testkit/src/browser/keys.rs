//! What a key press looks like to a page: the `key` and `code` of its keyboard events, the
//! Windows key code that Chromium needs to make them, and the text it types, if any.
//! macroquad on the web reads `event.code` for key presses and `charCode` for typed text.

/// One key: (`key`, `code`, Windows virtual key code, typed text).
pub(crate) type Key = (String, String, u32, Option<String>);

/// The key named `name`: a single printable ASCII character (`"a"`, `"7"`, `" "`), or one of
/// the names of `KeyboardEvent.key` for keys that type nothing (`"Enter"`, `"Escape"`,
/// `"Tab"`, `"Backspace"`, `"Delete"`, `"ArrowLeft"`, `"ArrowRight"`, `"ArrowUp"`,
/// `"ArrowDown"`, `"Home"`, `"End"`, `"PageUp"`, `"PageDown"`); `"Space"` is the space bar.
pub(crate) fn key(name: &str) -> Option<Key> {
    let named = |key: &str, code: &str, vk: u32, text: Option<&str>| {
        Some((
            key.to_string(),
            code.to_string(),
            vk,
            text.map(str::to_string),
        ))
    };
    match name {
        "Enter" => return named("Enter", "Enter", 13, Some("\r")),
        "Escape" => return named("Escape", "Escape", 27, None),
        "Tab" => return named("Tab", "Tab", 9, None),
        "Backspace" => return named("Backspace", "Backspace", 8, None),
        "Delete" => return named("Delete", "Delete", 46, None),
        "ArrowLeft" => return named("ArrowLeft", "ArrowLeft", 37, None),
        "ArrowUp" => return named("ArrowUp", "ArrowUp", 38, None),
        "ArrowRight" => return named("ArrowRight", "ArrowRight", 39, None),
        "ArrowDown" => return named("ArrowDown", "ArrowDown", 40, None),
        "Home" => return named("Home", "Home", 36, None),
        "End" => return named("End", "End", 35, None),
        "PageUp" => return named("PageUp", "PageUp", 33, None),
        "PageDown" => return named("PageDown", "PageDown", 34, None),
        "Space" | " " => return named(" ", "Space", 32, Some(" ")),
        _ => {}
    }
    let mut chars = name.chars();
    let (Some(c), None) = (chars.next(), chars.next()) else {
        return None;
    };
    let text = Some(c.to_string());
    let upper = c.to_ascii_uppercase();
    match c {
        'a'..='z' | 'A'..='Z' => Some((c.to_string(), format!("Key{upper}"), upper as u32, text)),
        '0'..='9' => Some((c.to_string(), format!("Digit{c}"), c as u32, text)),
        _ => {
            let (code, vk) = match c {
                '-' => ("Minus", 189),
                '=' => ("Equal", 187),
                ',' => ("Comma", 188),
                '.' => ("Period", 190),
                '/' => ("Slash", 191),
                ';' => ("Semicolon", 186),
                '\'' => ("Quote", 222),
                '[' => ("BracketLeft", 219),
                ']' => ("BracketRight", 221),
                '\\' => ("Backslash", 220),
                '`' => ("Backquote", 192),
                _ => return None,
            };
            Some((c.to_string(), code.to_string(), vk, text))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letters_digits_and_named_keys_have_their_codes() {
        assert_eq!(key("a").map(|k| (k.1, k.2)), Some(("KeyA".into(), 65)));
        assert_eq!(key("7").map(|k| (k.1, k.2)), Some(("Digit7".into(), 55)));
        assert_eq!(key("Space").map(|k| k.1), Some("Space".into()));
        assert_eq!(key("Escape").map(|k| k.3), Some(None));
    }

    #[test]
    fn unknown_names_are_refused() {
        assert_eq!(key("Hyper"), None);
        assert_eq!(key(""), None);
        assert_eq!(key("é"), None);
    }
}
