//! The player's name, as the other player and spectators see it: given once with `--name`,
//! remembered in the data directory beside the seats.

use std::fs;
use std::path::Path;

use breakshot_shared::protocol::is_valid_name;
use breakshot_shared::protocol::limits::MAX_NAME_CHARS;

/// The file under the data directory that holds the name.
pub(crate) const NAME_FILE: &str = "name";

/// The name to play under: `given` (checked, then remembered in `data`), else the name
/// remembered there, else the user's login name, else "player".
pub fn player_name(data: &Path, given: Option<&str>) -> Result<String, String> {
    if let Some(name) = given {
        let name = name.trim();
        if !is_valid_name(name) {
            return Err(format!(
                "--name {name:?}: a name is 1 to {MAX_NAME_CHARS} printable characters"
            ));
        }
        let saved = fs::create_dir_all(data).and_then(|()| fs::write(data.join(NAME_FILE), name));
        if let Err(e) = saved {
            tracing::warn!(error = %e, "cannot remember the name");
        }
        return Ok(name.to_owned());
    }
    let remembered = fs::read_to_string(data.join(NAME_FILE)).ok();
    let login = || {
        std::env::var("USER")
            .or_else(|_| std::env::var("USERNAME"))
            .ok()
    };
    Ok(remembered
        .map(|n| n.trim().to_owned())
        .filter(|n| is_valid_name(n))
        .or_else(|| {
            login()
                .map(|n| n.chars().take(MAX_NAME_CHARS).collect::<String>())
                .filter(|n| is_valid_name(n))
        })
        .unwrap_or_else(|| "player".to_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_name_is_remembered_and_a_bad_one_is_refused() {
        let dir = breakshot_testkit::scratch("name");
        let data = dir.path().join("data");
        assert_eq!(player_name(&data, Some(" ann ")).as_deref(), Ok("ann"));
        assert_eq!(player_name(&data, None).as_deref(), Ok("ann"));
        let long = "x".repeat(MAX_NAME_CHARS + 1);
        let refused = player_name(&data, Some(&long)).expect_err("too long");
        assert!(
            refused.contains("1 to 24 printable characters"),
            "{refused}"
        );
        assert!(player_name(&data, Some("a\u{7}b")).is_err());
        assert_eq!(player_name(&data, None).as_deref(), Ok("ann"), "unchanged");
    }

    #[test]
    fn without_a_remembered_name_one_is_still_valid() {
        let dir = breakshot_testkit::scratch("name-none");
        let name = player_name(dir.path(), None).expect("a name");
        assert!(is_valid_name(&name), "{name:?}");
    }
}
