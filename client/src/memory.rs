//! What the client remembers between runs, each in a small file of the data directory
//! (beside the seats): the player's name, given once with `--name`, and the view of the
//! table chosen last (top-down or 3-D), so the window opens on it next time; and the
//! player's key pair, made on first run, which is who the player is on every server.

use std::fs;
use std::path::Path;

#[cfg(not(target_arch = "wasm32"))]
use breakshot_shared::protocol::identity::SEED_LEN;
use breakshot_shared::protocol::is_valid_name;
use breakshot_shared::protocol::limits::MAX_NAME_CHARS;
#[cfg(not(target_arch = "wasm32"))]
use breakshot_shared::protocol::Identity;

use crate::view::ViewKind;

/// The file under the data directory that holds the name.
pub const NAME_FILE: &str = "name";
/// The file under the data directory that holds the view's name.
pub const VIEW_FILE: &str = "view";
/// The file under the data directory that holds the invite of the server whose lobby was
/// opened last.
pub const SERVER_FILE: &str = "lobby-server";
/// The file under the data directory that holds the secret of the player's key pair (32
/// bytes), readable by the user alone.
pub const KEY_FILE: &str = "player.key";

/// The text remembered in `data`'s `file`, if there is one.
fn recall(data: &Path, file: &str) -> Option<String> {
    fs::read_to_string(data.join(file)).ok()
}

/// Remembers `text` in `data`'s `file`, creating the directory if need be.
fn keep(data: &Path, file: &str, text: &str) -> std::io::Result<()> {
    fs::create_dir_all(data)?;
    fs::write(data.join(file), text)
}

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
        if let Err(e) = keep(data, NAME_FILE, name) {
            tracing::warn!(error = %e, "cannot remember the name");
        }
        return Ok(name.to_owned());
    }
    let login = || {
        std::env::var("USER")
            .or_else(|_| std::env::var("USERNAME"))
            .ok()
    };
    Ok(recall(data, NAME_FILE)
        .map(|n| n.trim().to_owned())
        .filter(|n| is_valid_name(n))
        .or_else(|| {
            login()
                .map(|n| n.chars().take(MAX_NAME_CHARS).collect::<String>())
                .filter(|n| is_valid_name(n))
        })
        .unwrap_or_else(|| "player".to_owned()))
}

/// The view remembered in `data`, if one was and it is readable.
pub fn remembered_view(data: &Path) -> Option<ViewKind> {
    ViewKind::parse(&recall(data, VIEW_FILE)?)
}

/// Remembers `view` in `data` for next time.
pub fn remember_view(data: &Path, view: ViewKind) -> std::io::Result<()> {
    keep(data, VIEW_FILE, view.name())
}

/// The server whose lobby was opened last (its invite without a room), if one was.
pub fn last_server(data: &Path) -> Option<breakshot_shared::protocol::Invite> {
    recall(data, SERVER_FILE)?.trim().parse().ok()
}

/// Remembers `server` as the lobby to open next time.
pub fn remember_server(
    data: &Path,
    server: &breakshot_shared::protocol::Invite,
) -> std::io::Result<()> {
    let mut server = server.clone();
    server.room = None;
    keep(data, SERVER_FILE, &server.to_string())
}

/// The player's key pair kept in `data`, made on first run. The file is created readable
/// and writable by the user alone, and made so again if it was opened up; a file that does
/// not hold a key is an error (a new key would be a new player, so it is not replaced).
#[cfg(not(target_arch = "wasm32"))]
pub fn identity(data: &Path) -> Result<Identity, String> {
    let path = data.join(KEY_FILE);
    match fs::read(&path) {
        Ok(bytes) => {
            let seed: [u8; SEED_LEN] = bytes.as_slice().try_into().map_err(|_| {
                format!(
                    "{} holds {} bytes, not a {SEED_LEN}-byte key; move it away to start as a new player",
                    path.display(),
                    bytes.len()
                )
            })?;
            private(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(Identity::from_seed(&seed))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let identity = crate::net::fresh_identity();
            fs::create_dir_all(data).map_err(|e| format!("{}: {e}", data.display()))?;
            write_private(&path, &identity.seed())
                .map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(identity)
        }
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

/// Writes a new file that only the user may read (`create_new`: an existing key is never
/// overwritten).
#[cfg(not(target_arch = "wasm32"))]
fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut options = fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.mode(0o600);
    }
    let mut file = options.open(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// Takes away any permission on the key file beyond the user's own.
#[cfg(not(target_arch = "wasm32"))]
fn private(path: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = fs::metadata(path)?.permissions().mode();
        if mode & 0o077 != 0 {
            tracing::warn!(path = %path.display(), "the key file was readable by others; it is made private");
            fs::set_permissions(path, fs::Permissions::from_mode(0o600))?;
        }
    }
    #[cfg(not(unix))]
    let _ = path;
    Ok(())
}

/// The file a drill's score is kept in: `drill-` and its name's letters and digits.
fn drill_file(name: &str) -> String {
    let slug: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    format!("drill-{slug}")
}

/// The score remembered for the drill called `name` (nothing yet: all zero).
pub fn drill_score(data: &Path, name: &str) -> crate::play::drill::Score {
    let text = recall(data, &drill_file(name)).unwrap_or_default();
    let n: Vec<u32> = text
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    match n[..] {
        [made, attempts, best] if made <= attempts && best <= made => crate::play::drill::Score {
            made,
            attempts,
            streak: 0,
            best,
        },
        _ => crate::play::drill::Score::default(),
    }
}

/// Remembers `score` for the drill called `name`.
pub fn remember_drill_score(
    data: &Path,
    name: &str,
    score: &crate::play::drill::Score,
) -> std::io::Result<()> {
    let text = format!("{} {} {}\n", score.made, score.attempts, score.best);
    keep(data, &drill_file(name), &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drill_s_score_is_remembered_and_a_damaged_one_is_forgotten() {
        let dir = breakshot_testkit::scratch("drill-score");
        let mut score = crate::play::drill::Score::default();
        for made in [true, true, false, true] {
            score.attempt(made);
        }
        remember_drill_score(dir.path(), "Straight in", &score).expect("kept");
        let back = drill_score(dir.path(), "Straight in");
        assert_eq!((back.made, back.attempts, back.best), (3, 4, 2));
        std::fs::write(dir.path().join("drill-straight-in"), "9 2 1").expect("written");
        assert_eq!(drill_score(dir.path(), "Straight in"), Default::default());
    }

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

    #[test]
    fn the_key_is_made_once_kept_private_and_never_replaced() {
        use std::os::unix::fs::PermissionsExt;
        let dir = breakshot_testkit::scratch("key");
        let data = dir.path().join("data");
        let first = identity(&data).expect("made");
        let path = data.join(KEY_FILE);
        let mode = fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600, "readable by the user alone");
        assert_eq!(identity(&data).expect("read").public(), first.public());
        fs::set_permissions(&path, fs::Permissions::from_mode(0o644)).unwrap();
        assert_eq!(identity(&data).expect("read").public(), first.public());
        let mode = fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600, "made private again");
        fs::write(&path, b"short").unwrap();
        let refused = identity(&data).expect_err("a spoilt key");
        assert!(refused.contains("not a 32-byte key"), "{refused}");
        assert_eq!(fs::read(&path).unwrap(), b"short", "not replaced");
    }

    #[test]
    fn the_view_chosen_is_remembered_and_a_spoilt_file_is_ignored() {
        let dir = breakshot_testkit::scratch("view-choice");
        let data = dir.path().join("data");
        assert_eq!(remembered_view(&data), None);
        remember_view(&data, ViewKind::ThreeD).expect("written");
        assert_eq!(remembered_view(&data), Some(ViewKind::ThreeD));
        remember_view(&data, ViewKind::TopDown).expect("written");
        assert_eq!(remembered_view(&data), Some(ViewKind::TopDown));
        fs::write(data.join(VIEW_FILE), "sideways").expect("written");
        assert_eq!(remembered_view(&data), None);
    }
}
