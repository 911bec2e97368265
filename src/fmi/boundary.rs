//! The C boundary: panic guard, instance handles, pointer-to-slice and string conversions.
//!
//! No panic may unwind into the importer (it would abort the host process): every export runs
//! under [`guard`] or [`catch_unwind`]. A panic inside an instance call becomes `fmi2Fatal` with a
//! logged message, and the instance then only accepts `fmi2FreeInstance`.

use std::any::Any;
use std::ffi::CStr;
use std::os::raw::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use super::handle;
use super::instance::{Instance, Outcome};
use super::machine::Mask;
use super::types::*;

/// The text of a panic payload.
pub fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-text payload".to_string()
    }
}

/// Runs `body` on the instance behind `c` under the handle check ([`handle::enter`]: freed and
/// foreign pointers, calls from inside the instance's own callbacks), the state machine and a
/// panic guard.
///
/// # Safety
/// `c` must be NULL, a handle returned by `fmi2Instantiate` (live or freed), or a pointer to at
/// least 8 readable bytes (see [`handle`] for the limits of the check).
pub unsafe fn guard(
    c: fmi2Component,
    func: &'static str,
    mask: Mask,
    body: impl FnOnce(&mut Instance) -> Outcome,
) -> fmi2Status {
    let Some(mut entered) = (unsafe { handle::enter(c, func) }) else {
        return fmi2Error;
    };
    let inst = entered.instance();
    let result = catch_unwind(AssertUnwindSafe(|| inst.call(func, mask, body)));
    match result {
        Ok(status) => status,
        Err(payload) => {
            let reason = panic_message(payload.as_ref());
            // The instance may be half-updated; marking it fatal only writes plain fields.
            let logged = catch_unwind(AssertUnwindSafe(|| inst.set_fatal(func, &reason)));
            if logged.is_err() {
                eprintln!("mbcosim: {func}: internal error: {reason}");
            }
            fmi2Fatal
        }
    }
}

/// A slice from an importer's array; `n = 0` gives an empty slice whatever the pointer.
///
/// # Safety
/// If `n > 0` and `p` is not NULL, `p` must point to `n` readable, initialized `T`.
pub unsafe fn in_slice<'a, T>(p: *const T, n: usize, what: &str) -> Outcome<&'a [T]> {
    if n == 0 {
        return Ok(&[]);
    }
    check_array(p, n, what)?;
    // SAFETY: non-NULL, aligned, length checked; validity is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice over an importer's output array; `n = 0` gives an empty slice.
///
/// # Safety
/// If `n > 0` and `p` is not NULL, `p` must point to `n` writable `T` not aliased elsewhere.
pub unsafe fn out_slice<'a, T>(p: *mut T, n: usize, what: &str) -> Outcome<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    check_array(p, n, what)?;
    // SAFETY: as for `in_slice`, plus exclusive access per the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

fn check_array<T>(p: *const T, n: usize, what: &str) -> Outcome<()> {
    if p.is_null() {
        return Err(format!("{what} is NULL but its length is {n}"));
    }
    if !p.is_aligned() {
        return Err(format!("{what} is not aligned for its element type"));
    }
    if n > isize::MAX as usize / size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    Ok(())
}

/// A mutable reference to an importer's output variable.
///
/// # Safety
/// If not NULL, `p` must point to a writable `T`.
pub unsafe fn out_ref<'a, T>(p: *mut T, what: &str) -> Outcome<&'a mut T> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !p.is_aligned() {
        return Err(format!("{what} is not aligned"));
    }
    // SAFETY: non-NULL and aligned; validity is the caller's contract.
    Ok(unsafe { &mut *p })
}

/// A UTF-8 string from an importer's C string.
///
/// # Safety
/// If not NULL, `p` must point to a NUL-terminated string.
pub unsafe fn c_str<'a>(p: *const c_char, what: &str) -> Outcome<&'a str> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated per the caller's contract.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|e| format!("{what} is not valid UTF-8 ({e})"))
}

/// The folder named by a `file:` URI (`file:///a/b%20c`, `file:/a/b`, `file://localhost/a/b`),
/// with a trailing slash allowed; `None` for other schemes or undecodable text.
pub fn path_from_file_uri(uri: &str) -> Option<PathBuf> {
    let rest = uri.strip_prefix("file:")?;
    let path = if let Some(r) = rest.strip_prefix("//") {
        // authority: empty or localhost
        let slash = r.find('/')?;
        let (host, p) = r.split_at(slash);
        if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
            return None;
        }
        p
    } else {
        rest
    };
    if !path.starts_with('/') {
        return None;
    }
    let mut bytes = Vec::with_capacity(path.len());
    let mut it = path.bytes();
    while let Some(b) = it.next() {
        if b == b'%' {
            let hi = (it.next()? as char).to_digit(16)?;
            let lo = (it.next()? as char).to_digit(16)?;
            bytes.push((hi * 16 + lo) as u8);
        } else {
            bytes.push(b);
        }
    }
    String::from_utf8(bytes).ok().map(PathBuf::from)
}

/// The resources folder named by `fmuResourceLocation`, or why it cannot be used (the text
/// names what was received). `location` is `Err` when the pointer was NULL or not UTF-8.
///
/// Accepted: a `file:` URI of an existing folder. A URI of the unpacked FMU's root (a folder
/// holding `modelDescription.xml` and `resources/`, which some importers pass) is taken to mean
/// its `resources/` folder; the second value is then a note saying so.
pub fn resource_folder(location: Outcome<&str>) -> Result<(PathBuf, Option<String>), String> {
    let uri = location?;
    let Some(path) = path_from_file_uri(uri) else {
        return Err(format!(
            "fmuResourceLocation `{}` is not a file:// URI of a local folder",
            uri.escape_debug()
        ));
    };
    existing_folder(path, "fmuResourceLocation", uri)
}

/// FMI 3.0's `resourcePath`: an absolute path of the resources folder, normally with a trailing
/// separator (a `file:` URI, as FMI 2.0 gives, is accepted too); otherwise as
/// [`resource_folder`].
pub fn resource_folder3(location: Outcome<&str>) -> Result<(PathBuf, Option<String>), String> {
    let text = location?;
    if text.starts_with("file:") {
        let path = path_from_file_uri(text).ok_or_else(|| {
            format!(
                "resourcePath `{}` is neither an absolute path nor a file:// URI of a local folder",
                text.escape_debug()
            )
        })?;
        return existing_folder(path, "resourcePath", text);
    }
    let path = PathBuf::from(text);
    if !path.is_absolute() {
        return Err(format!(
            "resourcePath `{}` is not an absolute path",
            text.escape_debug()
        ));
    }
    existing_folder(path, "resourcePath", text)
}

/// `path` when it is an existing folder; the FMU's root folder is taken to mean its
/// `resources/` folder, with a note saying so. `what` and `given` name the argument.
fn existing_folder(
    path: PathBuf,
    what: &str,
    given: &str,
) -> Result<(PathBuf, Option<String>), String> {
    if !path.is_dir() {
        return Err(format!(
            "{what} `{}` names {}, which is not an existing folder",
            given.escape_debug(),
            path.display()
        ));
    }
    let inner = path.join("resources");
    if path.join("modelDescription.xml").is_file() && inner.is_dir() {
        let note = format!(
            "{what} `{}` is the FMU's root folder, not its resources folder; using {}",
            given.escape_debug(),
            inner.display()
        );
        return Ok((inner, Some(note)));
    }
    Ok((path, None))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_folders_resolve_or_say_why_not() {
        let root = std::env::temp_dir().join(format!("mbcosim-res-{}", std::process::id()));
        let res = root.join("resources");
        std::fs::create_dir_all(&res).unwrap();
        std::fs::write(root.join("modelDescription.xml"), "<x/>").unwrap();
        let uri = |p: &std::path::Path| format!("file://{}", p.display());
        let (dir, note) = resource_folder(Ok(&uri(&res))).unwrap();
        assert_eq!((dir, note), (res.clone(), None));
        let (dir, note) = resource_folder(Ok(&uri(&root))).unwrap();
        assert_eq!(dir, res);
        assert!(note.unwrap().contains("root folder"));
        let e = resource_folder(Ok(res.to_str().unwrap())).unwrap_err();
        assert!(
            e.contains("not a file:// URI") && e.contains("resources"),
            "{e}"
        );
        let e = resource_folder(Ok(&uri(&root.join("missing")))).unwrap_err();
        assert!(
            e.contains("not an existing folder") && e.contains("missing"),
            "{e}"
        );
        let e = resource_folder(Err("fmuResourceLocation is NULL".into())).unwrap_err();
        assert!(e.contains("NULL"), "{e}");
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn file_uris_decode() {
        let p = |s: &str| path_from_file_uri(s).map(|p| p.to_string_lossy().into_owned());
        assert_eq!(
            p("file:///tmp/a%20b/resources"),
            Some("/tmp/a b/resources".into())
        );
        assert_eq!(p("file:/tmp/x/"), Some("/tmp/x/".into()));
        assert_eq!(p("file://localhost/tmp/x"), Some("/tmp/x".into()));
        assert_eq!(p("file://server/tmp/x"), None);
        assert_eq!(p("http://x/y"), None);
        assert_eq!(p("file:///bad%2"), None);
        assert_eq!(p("file:relative"), None);
    }

    #[test]
    fn slices_handle_null_and_zero_lengths() {
        let empty: &[f64] = unsafe { in_slice(std::ptr::null(), 0, "v") }.unwrap();
        assert!(empty.is_empty());
        let e = unsafe { in_slice::<f64>(std::ptr::null(), 3, "value[]") }.unwrap_err();
        assert!(e.contains("value[] is NULL"), "{e}");
        let e = unsafe { out_slice::<f64>(std::ptr::dangling_mut(), usize::MAX, "v") }.unwrap_err();
        assert!(e.contains("impossible"), "{e}");
        assert!(unsafe { c_str(std::ptr::null(), "name") }.is_err());
        assert_eq!(unsafe { c_str(c"abc".as_ptr(), "name") }.unwrap(), "abc");
        let payload: Box<dyn Any + Send> = Box::new("boom");
        assert_eq!(panic_message(payload.as_ref()), "boom");
    }
}
