//! Build script: links every artifact to one libm, and gives the FMUs' library a GNU build ID.
//!
//! libm: on x86_64 Linux, x86_64 Windows and aarch64 Linux, every link of this package (the
//! FMUs' library, the executables, tests, examples) gets `-Wl,-wrap,NAME` for each C math
//! function of src/fmi/c_math_symbols.rs, so that every call of `sin`, `pow`, ... in any object
//! file (ours, std's, nalgebra's, ...) goes to `__wrap_NAME` of src/fmi/c_math.rs, the `libm`
//! crate, instead of the C runtime's (docs/platforms.md, "One libm in every artifact").
//!
//! Build ID: on Linux the cdylib is linked with `-Wl,--build-id=sha1`, which ties the stripped
//! library to its split debug info (zig's linker writes none unless asked). On x86_64 Linux the
//! cdylib of the host build is the FMUs' portable library: scripts/link_host.sh links it with
//! zig against glibc 2.17 (.cargo/config.toml, docs/portable_binary.md); `MBCOSIM_PORTABLE=0`
//! asks for the host linker, so a change of it relinks.

// WRAPPED, WRAPPED_WINDOWS: the C math symbols src/fmi/c_math.rs defines `__wrap_<name>` for.
include!("src/fmi/c_math_symbols.rs");

/// The linker arguments that send every reference to a wrapped C math symbol to
/// `__wrap_<name>`, for the target cargo builds for (empty where src/fmi/c_math.rs defines no
/// trampolines). `-u __wrap_<name>` makes GNU ld take the definition from the library's rlib
/// while it reads it, before the rlibs of std and the dependencies that call it. The one-dash
/// spellings `-wrap` and `-u` are the ones that GNU ld, mingw-w64's ld and zig's `cc` (which
/// rejects `--wrap` and `--undefined`) all accept.
fn libm_link_args(arch: &str, os: &str) -> Vec<String> {
    let supported = matches!(
        (arch, os),
        ("x86_64", "linux" | "windows") | ("aarch64", "linux")
    );
    if !supported {
        return Vec::new();
    }
    let windows: &[&str] = if os == "windows" {
        &WRAPPED_WINDOWS
    } else {
        &[]
    };
    WRAPPED
        .iter()
        .chain(windows)
        .flat_map(|name| [format!("-Wl,-wrap,{name}"), format!("-Wl,-u,__wrap_{name}")])
        .collect()
}

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=src/fmi/c_math_symbols.rs");
    println!("cargo::rerun-if-env-changed=MBCOSIM_PORTABLE");
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    let (arch, os) = (var("CARGO_CFG_TARGET_ARCH"), var("CARGO_CFG_TARGET_OS"));
    for arg in libm_link_args(&arch, &os) {
        println!("cargo::rustc-link-arg={arg}");
    }
    if os == "linux" {
        println!("cargo::rustc-link-arg-cdylib=-Wl,--build-id=sha1");
    }
}
