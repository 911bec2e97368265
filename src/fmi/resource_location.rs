//! Where the FMU's resources are: `fmuResourceLocation` (FMI 2.0, a URI) and `resourcePath`
//! (FMI 3.0, an absolute path), and the scene file `scene.toml` read from there.
//!
//! The rules (docs/resource_location.md gives the reasons):
//! - a `file:` URI (scheme in any case: `file:`, `FILE:`) of an existing local folder is used;
//!   `file:///p`, `file:/p` and `file://localhost/p` are the same; percent escapes are decoded;
//! - NULL or an empty string: no resources given. The models that need no data file start from
//!   their built-in defaults with a Warning; the others are not instantiated;
//! - everything else that was given but cannot be used is an error at instantiation, never
//!   silently different physics: another scheme (`http:`), another host (`file://server/...`), a
//!   query or fragment, a bad percent escape, a missing folder, and a `scene.toml` that exists but
//!   cannot be read (symbolic-link loop, permissions, not a regular file, not UTF-8);
//! - a plain absolute path (FMI 2.0 asks for a URI, but the meaning is clear) is used, with a
//!   Warning; a relative path is an error (relative to what?);
//! - the unpacked FMU's root folder (holding `modelDescription.xml` and `resources/`) is taken to
//!   mean its `resources/` folder, with a Warning.
//!
//! Windows forms ([`local_path`] with `windows = true`: `file:///C:/dir`, `file:/C:/dir`,
//! `file://localhost/C:/dir`, UNC `file://server/share/dir` and `file:////server/share/dir`)
//! apply in the Windows DLL (`cfg!(windows)`); their unit tests run on every host, and
//! tests/python/test_platforms.py loads the DLL under wine through a percent-encoded
//! `file:///C:/...` URI (docs/platforms.md).

use std::path::{Path, PathBuf};

use super::instance::Outcome;
use crate::bounded_file;
use crate::scene::scene_file;

/// What the importer's resource location gives.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// The resources folder, with a note for a Warning when the value was taken to mean
    /// something slightly different from what the standard asks.
    Folder(PathBuf, Option<String>),
    /// No location was given (NULL or empty): why, for the Warning.
    Absent(String),
}

/// A `file:` URI: its host (`None` for the local machine: empty or `localhost`) and its decoded
/// path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileUri {
    pub host: Option<String>,
    pub path: String,
}

/// The scheme `text` starts with, lower-cased (RFC 3986: a letter, then letters, digits, `+`,
/// `-`, `.`, then `:`). A single letter is a Windows drive (`C:\dir`), not a scheme.
pub fn scheme(text: &str) -> Option<String> {
    let (head, _) = text.split_once(':')?;
    let mut chars = head.chars();
    let first = chars.next()?;
    let valid = first.is_ascii_alphabetic()
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'));
    (valid && head.len() > 1).then(|| head.to_ascii_lowercase())
}

/// `uri` split as a `file:` URI, or why it is not one this FMU can read (the text completes
/// "fmuResourceLocation `...` ...").
pub fn parse_file_uri(uri: &str) -> Result<FileUri, String> {
    match scheme(uri) {
        Some(s) if s == "file" => {}
        Some(s) => {
            return Err(format!(
                "uses the URI scheme `{s}:`; only `file:` URIs of a local folder can be read (the FMU does not download its resources)"
            ));
        }
        None => return Err("is not a URI (it has no scheme such as `file:`)".into()),
    }
    let rest = &uri[5..];
    if let Some(k) = rest.find('?') {
        return Err(format!(
            "has a query `{}`, which a file: URI of a folder cannot have (a `?` in a folder name is written %3F)",
            rest[k..].escape_debug()
        ));
    }
    if let Some(k) = rest.find('#') {
        return Err(format!(
            "has a fragment `{}`, which a file: URI of a folder cannot have (a `#` in a folder name is written %23)",
            rest[k..].escape_debug()
        ));
    }
    let (host, path) = match rest.strip_prefix("//") {
        Some(r) => {
            let (auth, path) = r.split_at(r.find('/').unwrap_or(r.len()));
            let local = auth.is_empty() || auth.eq_ignore_ascii_case("localhost");
            ((!local).then(|| percent_decode(auth)).transpose()?, path)
        }
        None => (None, rest),
    };
    let path = percent_decode(path)?;
    if path.is_empty() {
        return Err("names no folder (its path is empty)".into());
    }
    if path.contains('\0') {
        return Err("has an encoded NUL character (%00) in its path".into());
    }
    Ok(FileUri { host, path })
}

/// `%XX` escapes decoded; the result must be UTF-8.
fn percent_decode(s: &str) -> Result<String, String> {
    let mut bytes = Vec::with_capacity(s.len());
    let mut it = s.bytes();
    while let Some(b) = it.next() {
        if b != b'%' {
            bytes.push(b);
            continue;
        }
        let hex = |c: Option<u8>| c.and_then(|c| (c as char).to_digit(16));
        match (hex(it.next()), hex(it.next())) {
            (Some(hi), Some(lo)) => bytes.push((hi * 16 + lo) as u8),
            _ => {
                return Err(
                    "has a bad percent escape (`%` must be followed by two hex digits)".into(),
                );
            }
        }
    }
    String::from_utf8(bytes).map_err(|_| "decodes to text that is not UTF-8".into())
}

/// The local path `uri` names: with Windows rules when `windows` (drive letters, UNC paths for
/// another host), POSIX rules otherwise (another host cannot be read).
pub fn local_path(uri: &FileUri, windows: bool) -> Result<String, String> {
    if windows {
        let back = |p: &str| p.replace('/', "\\");
        if let Some(host) = &uri.host {
            return Ok(format!("\\\\{host}{}", back(&uri.path)));
        }
        if let Some(unc) = uri.path.strip_prefix("//") {
            return Ok(format!("\\\\{}", back(unc)));
        }
        let p = uri.path.strip_prefix('/').unwrap_or(&uri.path);
        let b = p.as_bytes();
        if b.len() >= 2 && b[0].is_ascii_alphabetic() && matches!(b[1], b':' | b'|') {
            let rest = back(&p[2..]);
            let rest = if rest.is_empty() {
                "\\".to_string()
            } else {
                rest
            };
            return Ok(format!("{}:{rest}", p[..1].to_ascii_uppercase()));
        }
        return Err(
            "has no drive letter or server (Windows needs file:///C:/... or file://server/share/...)"
                .into(),
        );
    }
    if let Some(host) = &uri.host {
        return Err(format!(
            "names the host `{host}`: a folder on another machine (a UNC path) cannot be read here; pass the local path, as file:///path/to/resources"
        ));
    }
    if !uri.path.starts_with('/') {
        return Err("has a relative path; a file: URI needs an absolute one (file:///path)".into());
    }
    Ok(uri.path.clone())
}

/// FMI 2.0's `fmuResourceLocation` (`None`: the pointer was NULL; `Some(Err)`: not UTF-8).
pub fn resource_folder(location: Option<Outcome<&str>>) -> Result<Location, String> {
    const WHAT: &str = "fmuResourceLocation";
    let text = match location {
        None => return Ok(Location::Absent(format!("{WHAT} is NULL"))),
        Some(t) => t?,
    };
    if text.is_empty() {
        return Ok(Location::Absent(format!("{WHAT} is empty")));
    }
    let shown = text.escape_debug();
    if scheme(text).is_some() {
        return from_uri(WHAT, text);
    }
    let path = Path::new(text);
    if !path.is_absolute() {
        return Err(format!(
            "{WHAT} `{shown}` is neither a file: URI nor an absolute path (FMI 2.0 asks for the URI of the resources folder, as file:///path/to/resources)"
        ));
    }
    let (dir, note) = existing_folder(path.to_path_buf(), WHAT, text)?;
    let plain = format!(
        "{WHAT} `{shown}` is a plain path, not a file: URI as FMI 2.0 asks; it is used as the resources folder"
    );
    Ok(Location::Folder(
        dir,
        Some(note.map_or(plain.clone(), |n| format!("{plain}; {n}"))),
    ))
}

/// FMI 3.0's `resourcePath`: an absolute path, normally with a trailing separator (a `file:` URI,
/// as FMI 2.0 gives, is accepted too); otherwise as [`resource_folder`].
pub fn resource_folder3(location: Option<Outcome<&str>>) -> Result<Location, String> {
    const WHAT: &str = "resourcePath";
    let text = match location {
        None => return Ok(Location::Absent(format!("{WHAT} is NULL"))),
        Some(t) => t?,
    };
    if text.is_empty() {
        return Ok(Location::Absent(format!("{WHAT} is empty")));
    }
    if scheme(text).is_some() {
        return from_uri(WHAT, text);
    }
    let path = PathBuf::from(text);
    if !path.is_absolute() {
        return Err(format!(
            "{WHAT} `{}` is not an absolute path (FMI 3.0 asks for the absolute path of the resources folder)",
            text.escape_debug()
        ));
    }
    let (dir, note) = existing_folder(path, WHAT, text)?;
    Ok(Location::Folder(dir, note))
}

fn from_uri(what: &str, uri: &str) -> Result<Location, String> {
    let path = parse_file_uri(uri)
        .and_then(|u| local_path(&u, cfg!(windows)))
        .map_err(|why| format!("{what} `{}` {why}", uri.escape_debug()))?;
    let (dir, note) = existing_folder(PathBuf::from(path), what, uri)?;
    Ok(Location::Folder(dir, note))
}

/// `path` when it is an existing folder; the FMU's root folder is taken to mean its
/// `resources/` folder, with a note saying so. `what` and `given` name the argument.
fn existing_folder(
    path: PathBuf,
    what: &str,
    given: &str,
) -> Result<(PathBuf, Option<String>), String> {
    let given = given.escape_debug();
    match std::fs::metadata(&path) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(format!(
                "{what} `{given}` names {}, which is a file, not a folder",
                path.display()
            ));
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(format!(
                "{what} `{given}` names {}, which is not an existing folder",
                path.display()
            ));
        }
        Err(e) => {
            return Err(format!(
                "{what} `{given}` names {}, which cannot be read ({e})",
                path.display()
            ));
        }
    }
    let inner = path.join("resources");
    if path.join("modelDescription.xml").is_file() && inner.is_dir() {
        let note = format!(
            "{what} `{given}` is the FMU's root folder, not its resources folder; using {}",
            inner.display()
        );
        return Ok((inner, Some(note)));
    }
    Ok((path, None))
}

/// The text of the scene file at `path`; `None` when there is none; otherwise why it cannot be
/// read: a symbolic-link loop or a dangling link, permissions, not a regular file (a FIFO, a
/// device, a folder), larger than [`scene_file::SCENE_FILE_BYTES`], not UTF-8. Read through
/// [`bounded_file`], which neither blocks nor reads past the cap.
pub fn read_scene_text(path: &Path) -> Result<Option<String>, String> {
    match bounded_file::read_text(path, &scene_file::SCENE_FILE) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.missing => Ok(None),
        Err(e) => Err(e.message),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unix(uri: &str) -> Result<String, String> {
        parse_file_uri(uri).and_then(|u| local_path(&u, false))
    }

    fn win(uri: &str) -> Result<String, String> {
        parse_file_uri(uri).and_then(|u| local_path(&u, true))
    }

    #[test]
    fn schemes_are_case_insensitive_and_drive_letters_are_not_schemes() {
        assert_eq!(scheme("FILE:///x").as_deref(), Some("file"));
        assert_eq!(scheme("File:/x").as_deref(), Some("file"));
        assert_eq!(scheme("svn+ssh://h/x").as_deref(), Some("svn+ssh"));
        assert_eq!(scheme("C:\\dir"), None);
        assert_eq!(scheme("/tmp/a:b"), None);
        assert_eq!(scheme("not a uri"), None);
        assert_eq!(scheme("1abc:x"), None);
    }

    #[test]
    fn posix_file_uris() {
        let ok = |u: &str| unix(u).unwrap();
        assert_eq!(ok("file:///tmp/a%20b/resources"), "/tmp/a b/resources");
        assert_eq!(ok("FILE:///tmp/x"), "/tmp/x");
        assert_eq!(ok("file:/tmp/x/"), "/tmp/x/");
        assert_eq!(ok("file://localhost/tmp/x"), "/tmp/x");
        assert_eq!(ok("file://LOCALHOST/tmp/x"), "/tmp/x");
        assert_eq!(ok("file:///tmp/%3F%23"), "/tmp/?#");
        let err = |u: &str| unix(u).unwrap_err();
        assert!(err("file://server/tmp/x").contains("host `server`"));
        assert!(err("http://x/y").contains("scheme `http:`"));
        assert!(err("file:///tmp/x?a=1").contains("query `?a=1`"));
        assert!(err("file:///tmp/x#top").contains("fragment `#top`"));
        assert!(err("file:///bad%2").contains("percent escape"));
        assert!(err("file:///bad%zz").contains("percent escape"));
        assert!(err("file:///a%ff").contains("UTF-8"));
        assert!(err("file:///a%00b").contains("NUL"));
        assert!(err("file:relative").contains("relative"));
        assert!(err("file://").contains("no folder"));
        assert!(err("tmp/x").contains("not a URI"));
    }

    #[test]
    fn windows_file_uris() {
        let ok = |u: &str| win(u).unwrap();
        assert_eq!(
            ok("file:///C:/Users/a%20b/resources"),
            "C:\\Users\\a b\\resources"
        );
        assert_eq!(ok("file:/c:/x/"), "C:\\x\\");
        assert_eq!(ok("file://localhost/D:/x"), "D:\\x");
        assert_eq!(ok("file:///C|/x"), "C:\\x");
        assert_eq!(ok("file:///C:"), "C:\\");
        assert_eq!(
            ok("file://server/share/fmu/resources"),
            "\\\\server\\share\\fmu\\resources"
        );
        assert_eq!(ok("file:////server/share/x"), "\\\\server\\share\\x");
        assert_eq!(
            ok("file://server/share/a%20b%23c"),
            "\\\\server\\share\\a b#c"
        );
        assert_eq!(ok("file:///C%3A/x%25y"), "C:\\x%y");
        assert_eq!(ok("FILE:/d:/"), "D:\\");
        assert!(
            win("file:///no/drive")
                .unwrap_err()
                .contains("drive letter")
        );
    }

    #[test]
    fn resource_folders_resolve_or_say_why_not() {
        let root = std::env::temp_dir().join(format!("mbcosim-res-{}", std::process::id()));
        let res = root.join("resources");
        std::fs::create_dir_all(&res).unwrap();
        std::fs::write(root.join("modelDescription.xml"), "<x/>").unwrap();
        let uri = |p: &Path| format!("file://{}", p.display());
        let folder = |l: Result<Location, String>| match l.unwrap() {
            Location::Folder(d, n) => (d, n),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            folder(resource_folder(Some(Ok(&uri(&res))))),
            (res.clone(), None)
        );
        let (dir, note) = folder(resource_folder(Some(Ok(&uri(&root)))));
        assert_eq!(dir, res);
        assert!(note.unwrap().contains("root folder"));
        let (dir, note) = folder(resource_folder(Some(Ok(res.to_str().unwrap()))));
        assert_eq!(dir, res);
        assert!(note.unwrap().contains("plain path"));
        let e = resource_folder(Some(Ok("resources"))).unwrap_err();
        assert!(
            e.contains("neither a file: URI nor an absolute path"),
            "{e}"
        );
        let e = resource_folder(Some(Ok(&uri(&root.join("missing"))))).unwrap_err();
        assert!(
            e.contains("not an existing folder") && e.contains("missing"),
            "{e}"
        );
        let e = resource_folder(Some(Ok(&uri(&root.join("modelDescription.xml"))))).unwrap_err();
        assert!(e.contains("a file, not a folder"), "{e}");
        assert_eq!(
            resource_folder(None),
            Ok(Location::Absent("fmuResourceLocation is NULL".into()))
        );
        assert!(matches!(
            resource_folder(Some(Ok(""))),
            Ok(Location::Absent(_))
        ));
        assert!(resource_folder(Some(Err("not UTF-8".into()))).is_err());
        // FMI 3.0
        let with_sep = format!("{}/", res.display());
        assert_eq!(
            folder(resource_folder3(Some(Ok(&with_sep)))).0,
            res.join("")
        );
        assert!(matches!(
            resource_folder3(Some(Ok(&uri(&res).replace("file:", "FILE:")))),
            Ok(Location::Folder(..))
        ));
        let e = resource_folder3(Some(Ok("resources/"))).unwrap_err();
        assert!(e.contains("not an absolute path"), "{e}");
        assert!(matches!(resource_folder3(None), Ok(Location::Absent(_))));
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn scene_files_that_cannot_be_read_say_why() {
        let dir = std::env::temp_dir().join(format!("mbcosim-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("scene.toml");
        assert_eq!(read_scene_text(&p), Ok(None));
        std::fs::write(&p, "a = 1\n").unwrap();
        assert_eq!(read_scene_text(&p), Ok(Some("a = 1\n".into())));
        std::fs::write(&p, b"a = \xff\n").unwrap();
        assert!(read_scene_text(&p).unwrap_err().contains("offset 4"));
        std::fs::remove_file(&p).unwrap();
        std::os::unix::fs::symlink("scene.toml", &p).unwrap();
        let e = read_scene_text(&p).unwrap_err();
        assert!(
            e.contains("cannot read") && e.contains("symbolic links"),
            "{e}"
        );
        std::fs::remove_file(&p).unwrap();
        std::os::unix::fs::symlink("nowhere.toml", &p).unwrap();
        assert!(read_scene_text(&p).unwrap_err().contains("nowhere.toml"));
        std::fs::remove_file(&p).unwrap();
        std::fs::create_dir(&p).unwrap();
        assert!(
            read_scene_text(&p)
                .unwrap_err()
                .contains("not a regular file")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
