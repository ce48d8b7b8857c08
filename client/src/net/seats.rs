//! The seats this computer holds in games on other servers (or its own): the seat token of
//! each, so that closing the window, a crash or a restarted host does not give the game
//! away. One small file per server and room under `seats/` in the data directory, readable
//! only by the user (a token is what proves the seat is ours); in the browser, one entry per
//! server and room in the page's `localStorage`.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use breakshot_shared::protocol::{Fingerprint, Invite, RoomCode, SeatToken};

/// The directory of remembered seats, under a data directory (or the page's storage).
#[derive(Clone, Debug)]
pub struct SeatStore {
    dir: PathBuf,
    /// In the browser: the page's `localStorage` instead of `dir`.
    #[cfg(target_arch = "wasm32")]
    page: bool,
}

/// A remembered seat: the invite of its room and the token that takes it back.
#[derive(Clone, Debug, PartialEq)]
pub struct Remembered {
    /// The invite the seat was taken with (its server, room and fingerprint).
    pub invite: Invite,
    /// The seat token.
    pub token: SeatToken,
}

impl SeatStore {
    /// The seats remembered under `data` (nothing is written until a seat is saved).
    pub fn new(data: &Path) -> SeatStore {
        SeatStore {
            dir: data.join("seats"),
            #[cfg(target_arch = "wasm32")]
            page: false,
        }
    }

    /// The seats the page remembers in its `localStorage` (kept per site by the browser).
    #[cfg(target_arch = "wasm32")]
    pub fn page() -> SeatStore {
        SeatStore {
            dir: PathBuf::new(),
            page: true,
        }
    }

    /// The page's storage key of a room's seat: its server and room (a page dials by
    /// address; the invite's fingerprint is not the page's to check).
    #[cfg(target_arch = "wasm32")]
    fn page_key(invite: &Invite) -> Option<String> {
        let room = invite.room.as_ref()?;
        Some(format!(
            "breakshot.seat {}/{room}",
            invite.first().authority()
        ))
    }

    /// The file of one server's room: named by the certificate fingerprint (which stays
    /// the same when the server's address changes) and the room code.
    fn file(&self, fingerprint: &Fingerprint, room: &RoomCode) -> PathBuf {
        self.dir.join(format!("{fingerprint}-{room}"))
    }

    /// Remembers the seat `token` holds in the room of `invite`. Written to a temporary file
    /// created readable by the user alone, then renamed, so a crash leaves the old file or
    /// the new one.
    pub fn save(&self, invite: &Invite, token: SeatToken) -> std::io::Result<()> {
        let Some(room) = &invite.room else {
            return Ok(());
        };
        #[cfg(target_arch = "wasm32")]
        if self.page {
            if let Some(key) = SeatStore::page_key(invite) {
                super::page::store(&key, &hex(&token.0));
            }
            return Ok(());
        }
        fs::create_dir_all(&self.dir)?;
        let path = self.file(&invite.fingerprint, room);
        let tmp = path.with_extension("tmp");
        let mut options = fs::OpenOptions::new();
        options.write(true).create(true).truncate(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt as _;
            options.mode(0o600);
        }
        let mut file = options.open(&tmp)?;
        writeln!(file, "{invite}\n{}", hex(&token.0))?;
        file.sync_all()?;
        fs::rename(tmp, path)
    }

    /// The token remembered for the room of `invite`, if any.
    pub fn load(&self, invite: &Invite) -> Option<SeatToken> {
        #[cfg(target_arch = "wasm32")]
        if self.page {
            let kept = super::page::stored(&SeatStore::page_key(invite)?)?;
            return unhex(kept.trim()).map(SeatToken);
        }
        let room = invite.room.as_ref()?;
        let found = read(&self.file(&invite.fingerprint, room))?;
        Some(found.token)
    }

    /// Forgets the seat in the room of `invite` (the game is over or the token is stale).
    pub fn forget(&self, invite: &Invite) {
        #[cfg(target_arch = "wasm32")]
        if self.page {
            if let Some(key) = SeatStore::page_key(invite) {
                super::page::unstore(&key);
            }
            return;
        }
        if let Some(room) = &invite.room {
            let _ = fs::remove_file(self.file(&invite.fingerprint, room));
        }
    }

    /// Every remembered seat, most recently saved first. Unreadable files are skipped.
    pub fn all(&self) -> Vec<Remembered> {
        let Ok(entries) = fs::read_dir(&self.dir) else {
            return Vec::new();
        };
        let mut found: Vec<(std::time::SystemTime, Remembered)> = entries
            .flatten()
            .filter(|e| e.path().extension().is_none())
            .filter_map(|e| {
                let when = e.metadata().and_then(|m| m.modified()).ok()?;
                Some((when, read(&e.path())?))
            })
            .collect();
        found.sort_by_key(|f| std::cmp::Reverse(f.0));
        found.into_iter().map(|(_, r)| r).collect()
    }

    /// The most recent seat remembered on the server with `fingerprint`.
    pub fn on_server(&self, fingerprint: &Fingerprint) -> Option<Remembered> {
        self.all()
            .into_iter()
            .find(|r| &r.invite.fingerprint == fingerprint)
    }
}

/// True when the server with `fingerprint` is the one this computer hosts from `data` (its
/// certificate is there): such a seat is taken back by hosting again, not by dialling.
pub fn hosted_from(data: &Path, fingerprint: &Fingerprint) -> bool {
    use sha2::{Digest as _, Sha256};
    fs::read(data.join("cert.der"))
        .is_ok_and(|der| Fingerprint(Sha256::digest(&der).into()) == *fingerprint)
}

/// Reads a seat file: the invite on the first line, the token in hex on the second.
fn read(path: &Path) -> Option<Remembered> {
    let text = fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let invite: Invite = lines.next()?.trim().parse().ok()?;
    invite.room.as_ref()?;
    let token = unhex(lines.next()?.trim())?;
    Some(Remembered {
        invite,
        token: SeatToken(token),
    })
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex(text: &str) -> Option<[u8; 16]> {
    if text.len() != 32 || !text.is_ascii() {
        return None;
    }
    let mut out = [0u8; 16];
    for (i, byte) in out.iter_mut().enumerate() {
        *byte = u8::from_str_radix(&text[2 * i..2 * i + 2], 16).ok()?;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn invite(room: &str) -> Invite {
        format!("breakshot://192.168.1.20:4433/{room}#{}", "ab".repeat(32))
            .parse()
            .unwrap()
    }

    #[test]
    fn a_saved_seat_is_found_again_and_only_the_user_can_read_it() {
        let tmp = breakshot_testkit::scratch("save");
        let dir = tmp.path().to_path_buf();
        let store = SeatStore::new(&dir);
        let (a, b) = (invite("K7QX2M4B"), invite("ZZQX2M4B"));
        assert_eq!(store.load(&a), None);
        store.save(&a, SeatToken([7; 16])).unwrap();
        assert_eq!(store.load(&a), Some(SeatToken([7; 16])));
        assert_eq!(store.load(&b), None, "another room has no seat");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let file = store.file(&a.fingerprint, a.room.as_ref().unwrap());
            let mode = fs::metadata(file).unwrap().permissions().mode();
            assert_eq!(mode & 0o777, 0o600);
        }
        assert_eq!(
            store.on_server(&a.fingerprint).map(|r| r.invite),
            Some(a.clone())
        );
        store.forget(&a);
        assert_eq!(store.load(&a), None);
        assert!(store.all().is_empty());
    }

    #[test]
    fn a_damaged_seat_file_is_no_seat() {
        let tmp = breakshot_testkit::scratch("damaged");
        let dir = tmp.path().to_path_buf();
        let store = SeatStore::new(&dir);
        let a = invite("K7QX2M4B");
        store.save(&a, SeatToken([1; 16])).unwrap();
        let file = store.file(&a.fingerprint, a.room.as_ref().unwrap());
        fs::write(&file, format!("{a}\nnot hex at all, no no no no no\n")).unwrap();
        assert_eq!(store.load(&a), None);
        assert!(store.all().is_empty());
    }
}
