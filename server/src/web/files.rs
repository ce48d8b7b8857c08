//! Which file of the web directory a request path names, refusing every way out of it, and
//! the Content-Type it is served with.

use std::path::{Path, PathBuf};

/// Why a path names no file to serve.
#[derive(Debug, PartialEq, Eq)]
pub enum Refused {
    /// A malformed path or an attempt to leave the directory (`..`, a backslash, NUL, a bad
    /// %-escape): 400.
    Bad,
    /// No such file in the directory (or a hidden one, or one a symbolic link takes
    /// outside it): 404.
    Missing,
}

/// The file `target` (the request target, origin form, query allowed) names under `root`
/// (an already canonical directory). `/` and any directory give its `index.html`.
pub fn resolve(root: &Path, target: &str) -> Result<PathBuf, Refused> {
    let path = target.split(['?', '#']).next().unwrap_or("");
    if !path.starts_with('/') {
        return Err(Refused::Bad);
    }
    let decoded = percent_decode(path).ok_or(Refused::Bad)?;
    if decoded.contains(['\0', '\\']) {
        return Err(Refused::Bad);
    }
    let mut file = root.to_path_buf();
    for segment in decoded.split('/').filter(|s| !s.is_empty()) {
        if segment == "." || segment == ".." {
            return Err(Refused::Bad);
        }
        // Hidden files (a `.git`, an editor's leftovers) are never part of the bundle.
        if segment.starts_with('.') {
            return Err(Refused::Missing);
        }
        file.push(segment);
    }
    // Symbolic links are followed, then the result must still be inside the directory.
    let mut real = file.canonicalize().map_err(|_| Refused::Missing)?;
    if real.is_dir() {
        real = real
            .join("index.html")
            .canonicalize()
            .map_err(|_| Refused::Missing)?;
    }
    if !real.starts_with(root) || !real.is_file() {
        return Err(Refused::Missing);
    }
    Ok(real)
}

/// Decodes %-escapes; `None` for a bad escape or bytes that are not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The Content-Type of a file, by its extension.
pub fn content_type(path: &Path) -> &'static str {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("html" | "htm") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("wasm") => "application/wasm",
        Some("css") => "text/css; charset=utf-8",
        Some("png") => "image/png",
        Some("json") => "application/json",
        Some("txt") => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> (tempfile::TempDir, PathBuf) {
        let tmp = tempfile::tempdir().unwrap();
        let root = tmp.path().join("web");
        std::fs::create_dir_all(root.join("sub")).unwrap();
        std::fs::write(root.join("index.html"), "<p>").unwrap();
        std::fs::write(root.join("a b.js"), "x").unwrap();
        std::fs::write(root.join("sub/index.html"), "s").unwrap();
        std::fs::write(root.join(".hidden"), "h").unwrap();
        std::fs::write(tmp.path().join("secret.txt"), "no").unwrap();
        std::os::unix::fs::symlink(tmp.path().join("secret.txt"), root.join("out.txt")).unwrap();
        std::os::unix::fs::symlink(root.join("index.html"), root.join("in.html")).unwrap();
        let root = root.canonicalize().unwrap();
        (tmp, root)
    }

    #[test]
    fn paths_inside_resolve() {
        let (_tmp, root) = dir();
        assert_eq!(resolve(&root, "/"), Ok(root.join("index.html")));
        assert_eq!(resolve(&root, "/?room=X#f"), Ok(root.join("index.html")));
        assert_eq!(resolve(&root, "/a%20b.js"), Ok(root.join("a b.js")));
        assert_eq!(resolve(&root, "/sub/"), Ok(root.join("sub/index.html")));
        assert_eq!(resolve(&root, "//index.html"), Ok(root.join("index.html")));
        assert_eq!(resolve(&root, "/in.html"), Ok(root.join("index.html")));
    }

    #[test]
    fn every_way_out_is_refused() {
        let (_tmp, root) = dir();
        for bad in [
            "/../secret.txt",
            "/%2e%2e/secret.txt",
            "/%2E%2E/secret.txt",
            "/..%2fsecret.txt",
            "/sub/../../secret.txt",
            "/.",
            "/a%5c..%5csecret.txt",
            "/\\..\\secret.txt",
            "/index.html%00",
            "/%zz",
            "/%ff",
            "index.html",
            "http://example.org/",
            "*",
        ] {
            assert_eq!(resolve(&root, bad), Err(Refused::Bad), "{bad}");
        }
        for missing in [
            "/out.txt",
            "/.hidden",
            "/nope.js",
            "/sub/nope",
            "/index.html/x",
        ] {
            assert_eq!(resolve(&root, missing), Err(Refused::Missing), "{missing}");
        }
    }

    #[test]
    fn content_types_by_extension() {
        for (name, want) in [
            ("a.html", "text/html; charset=utf-8"),
            ("a.js", "text/javascript; charset=utf-8"),
            ("a.WASM", "application/wasm"),
            ("a.css", "text/css; charset=utf-8"),
            ("a.png", "image/png"),
            ("a.json", "application/json"),
            ("a.txt", "text/plain; charset=utf-8"),
            ("a", "application/octet-stream"),
        ] {
            assert_eq!(content_type(Path::new(name)), want);
        }
    }
}
