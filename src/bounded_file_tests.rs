//! Tests of the bounded reader: every hostile kind of path is refused quickly, with the path,
//! the kind of file and (for a size) the cap in the message. The reads that never end on plain
//! `std::fs::read` (a FIFO, `/dev/zero`, `/dev/urandom`) run on a thread that must answer within
//! 10 s, so a regression fails the test instead of hanging it.

use super::*;
use std::os::unix::fs::MetadataExt;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

const SMALL: FileKind = FileKind {
    what: "test file",
    max_bytes: 100,
    cap_name: "TEST_CAP",
};

/// A fresh scratch folder for `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mbcosim-bounded-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `read_bytes(path, kind)` on a thread; panics if it has not returned within 10 s.
fn read_within_10_s(path: &Path, kind: FileKind) -> Result<Vec<u8>, ReadError> {
    let (tx, rx) = mpsc::channel();
    let p = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = tx.send(read_bytes(&p, &kind));
    });
    rx.recv_timeout(Duration::from_secs(10))
        .unwrap_or_else(|_| panic!("reading {} did not return within 10 s", path.display()))
}

fn refused(path: &Path, kind: FileKind) -> String {
    match read_within_10_s(path, kind) {
        Ok(b) => panic!("{} was read ({} bytes)", path.display(), b.len()),
        Err(e) => {
            assert!(!e.missing, "{e}");
            e.message
        }
    }
}

#[test]
fn a_regular_file_within_its_cap_is_read_and_an_absent_one_is_missing() {
    let dir = scratch("regular");
    let p = dir.join("a.toml");
    std::fs::write(&p, "a = 1\n").unwrap();
    assert_eq!(read_text(&p, &SMALL).unwrap(), "a = 1\n");
    std::fs::write(&p, vec![b'x'; 100]).unwrap();
    assert_eq!(
        read_bytes(&p, &SMALL).unwrap().len(),
        100,
        "exactly the cap is read"
    );
    // through a symbolic link to a regular file
    let link = dir.join("link.toml");
    std::os::unix::fs::symlink("a.toml", &link).unwrap();
    assert_eq!(read_bytes(&link, &SMALL).unwrap().len(), 100);
    let e = read_bytes(&dir.join("none.toml"), &SMALL).unwrap_err();
    assert!(e.missing && e.message.contains("none.toml"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fifo_is_refused_without_blocking() {
    let dir = scratch("fifo");
    let p = dir.join("block.obj");
    let made = std::process::Command::new("mkfifo")
        .arg(&p)
        .status()
        .unwrap();
    assert!(made.success());
    let e = refused(&p, SMALL);
    assert!(
        e.contains("FIFO") && e.contains("not a regular file") && e.contains("block.obj"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn endless_devices_are_refused_before_a_byte_is_read() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        let e = refused(Path::new(dev), SMALL);
        assert!(
            e.contains("character device") && e.contains(dev) && e.contains("test file"),
            "{e}"
        );
    }
    // a link to a device is followed, and the device refused
    let dir = scratch("devlink");
    let p = dir.join("mesh.stl");
    std::os::unix::fs::symlink("/dev/zero", &p).unwrap();
    assert!(refused(&p, SMALL).contains("character device"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn folders_loops_and_dangling_links_say_what_they_are() {
    let dir = scratch("kinds");
    let folder = dir.join("scene.toml");
    std::fs::create_dir(&folder).unwrap();
    let e = refused(&folder, SMALL);
    assert!(
        e.contains("a folder") && e.contains("not a regular file"),
        "{e}"
    );
    let looped = dir.join("loop.toml");
    std::os::unix::fs::symlink("loop.toml", &looped).unwrap();
    let e = refused(&looped, SMALL);
    assert!(
        e.contains("symbolic-link loop") && e.contains("loop.toml") && e.contains("cannot read"),
        "{e}"
    );
    // a loop of two links
    std::os::unix::fs::symlink("b.toml", dir.join("a.toml")).unwrap();
    std::os::unix::fs::symlink("a.toml", dir.join("b.toml")).unwrap();
    assert!(refused(&dir.join("a.toml"), SMALL).contains("symbolic-link loop"));
    let dangling = dir.join("dangling.toml");
    std::os::unix::fs::symlink("nowhere.toml", &dangling).unwrap();
    let e = refused(&dangling, SMALL);
    assert!(
        e.contains("symbolic link to nowhere.toml, which does not exist"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_over_its_cap_is_refused_before_reading_naming_the_cap() {
    let dir = scratch("size");
    let p = dir.join("big.stl");
    // sparse: 100 GiB of nothing on disk; refused by its size, so never read
    let f = File::create(&p).unwrap();
    f.set_len(100 << 30).unwrap();
    let kind = FileKind {
        what: "mesh file",
        max_bytes: 256 << 20,
        cap_name: "MESH_FILE_BYTES",
    };
    let e = refused(&p, kind);
    assert!(
        e.contains("big.stl")
            && e.contains("cap of 256 MiB on a mesh file")
            && e.contains("MESH_FILE_BYTES = 268435456 bytes")
            && e.contains("it has 107374182400 bytes"),
        "{e}"
    );
    f.set_len(101).unwrap();
    let e = refused(&p, SMALL);
    assert!(
        e.contains("cap of 100 bytes") && e.contains("TEST_CAP"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_longer_than_its_size_says_is_cut_at_the_cap() {
    // /proc files are regular files of size 0 whose text is longer: only take(cap + 1) stops them
    let p = Path::new("/proc/self/maps");
    assert_eq!(std::fs::metadata(p).unwrap().len(), 0);
    let e = refused(p, SMALL);
    assert!(
        e.contains("grew past 100 bytes") && e.contains("TEST_CAP"),
        "{e}"
    );
}

#[test]
fn text_that_is_not_utf8_is_refused_with_the_offset() {
    let dir = scratch("utf8");
    let p = dir.join("scene.toml");
    std::fs::write(&p, b"a = \xff\n").unwrap();
    let e = read_text(&p, &SMALL).unwrap_err().message;
    assert!(
        e.contains("not valid UTF-8") && e.contains("offset 4"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The environment variable that hands [`child_reads_the_locked_file`] its path.
const LOCKED: &str = "MBCOSIM_BOUNDED_FILE_LOCKED";

#[test]
fn a_file_that_cannot_be_opened_is_refused_with_the_system_reason() {
    // root reads a mode-000 file (CAP_DAC_OVERRIDE): as root the read runs in a copy of this test
    // binary started by `setpriv` without that capability, so the open really fails
    let dir = scratch("locked");
    let p = dir.join("scene.toml");
    std::fs::write(&p, "a = 1\n").unwrap();
    std::fs::set_permissions(&p, std::os::unix::fs::PermissionsExt::from_mode(0o000)).unwrap();
    let root = std::fs::metadata(&p).unwrap().uid() == 0;
    let message = if root {
        let drop = "-dac_override,-dac_read_search";
        let out = std::process::Command::new("setpriv")
            .args(["--bounding-set", drop, "--inh-caps", drop])
            .arg(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "bounded_file::tests::child_reads_the_locked_file",
            ])
            .args(["--ignored", "--nocapture", "--test-threads", "1"])
            .env(LOCKED, &p)
            .output()
            .expect("setpriv (util-linux) is needed to run this test as root");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        stdout
    } else {
        refused(&p, SMALL)
    };
    assert!(
        message.contains("cannot read test file") && message.contains("scene.toml"),
        "{message}"
    );
    assert!(message.contains("Permission denied"), "{message}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Run by [`a_file_that_cannot_be_opened_is_refused_with_the_system_reason`] without the
/// capabilities that let root read any file; prints the refusal.
#[test]
#[ignore = "run by a_file_that_cannot_be_opened_is_refused_with_the_system_reason"]
fn child_reads_the_locked_file() {
    let p = std::env::var_os(LOCKED).expect("started by the parent test");
    println!("{}", refused(Path::new(&p), SMALL));
}

#[test]
fn a_head_is_read_with_the_checks_of_the_whole_file() {
    let dir = scratch("head");
    let p = dir.join("mesh.stl");
    std::fs::write(&p, b"0123456789").unwrap();
    assert_eq!(read_head(&p, &SMALL, 4).unwrap(), b"0123");
    assert_eq!(read_head(&p, &SMALL, 84).unwrap(), b"0123456789");
    File::options()
        .write(true)
        .open(&p)
        .unwrap()
        .set_len(101)
        .unwrap();
    assert!(
        read_head(&p, &SMALL, 4)
            .unwrap_err()
            .message
            .contains("TEST_CAP")
    );
    let e = read_head(Path::new("/dev/zero"), &SMALL, 4)
        .unwrap_err()
        .message;
    assert!(e.contains("character device"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
