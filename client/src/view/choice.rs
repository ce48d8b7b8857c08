//! The view the player chose last (top-down or 3-D), remembered in the data directory beside
//! the player's name, so the window opens on it next time.

use std::fs;
use std::path::Path;

use super::camera::ViewKind;

/// The file under the data directory that holds the view's name.
pub const VIEW_FILE: &str = "view";

/// The view remembered in `data`, if one was and it is readable.
pub fn remembered(data: &Path) -> Option<ViewKind> {
    ViewKind::parse(&fs::read_to_string(data.join(VIEW_FILE)).ok()?)
}

/// Remembers `view` in `data` for next time.
pub fn remember(data: &Path, view: ViewKind) -> std::io::Result<()> {
    fs::create_dir_all(data)?;
    fs::write(data.join(VIEW_FILE), view.name())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_chosen_is_remembered_and_a_spoilt_file_is_ignored() {
        let dir = breakshot_testkit::scratch("view-choice");
        let data = dir.path().join("data");
        assert_eq!(remembered(&data), None);
        remember(&data, ViewKind::ThreeD).expect("written");
        assert_eq!(remembered(&data), Some(ViewKind::ThreeD));
        remember(&data, ViewKind::TopDown).expect("written");
        assert_eq!(remembered(&data), Some(ViewKind::TopDown));
        fs::write(data.join(VIEW_FILE), "sideways").expect("written");
        assert_eq!(remembered(&data), None);
    }
}
