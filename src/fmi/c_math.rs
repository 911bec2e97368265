//! One implementation of the C math functions in every artifact: the Windows DLL, the x86_64
//! and aarch64 Linux libraries, the executables and the test binaries (docs/platforms.md, "One
//! libm in every artifact").
//!
//! `f64::sin` and friends, in our code as in nalgebra's, parry's and faer's, compile to calls
//! of the C symbols `sin`, `cos`, ... that the linker takes from the C runtime: glibc's libm on
//! Linux, `msvcrt.dll` on Windows, whose last bits differ (PanelLock's latch impacts amplify a
//! 5e-14 difference to 1.4e-5). build.rs passes `-Wl,-wrap,NAME` for every name of
//! [`WRAPPED`] (and [`WRAPPED_WINDOWS`] on Windows): the linker then resolves every reference
//! to `NAME`, in any object file of the link, to `__wrap_NAME`, defined here. Each
//! `__wrap_NAME` is a one-instruction trampoline in assembly (a tail jump to a Rust function
//! that calls the `libm` crate, pinned in Cargo.toml) with hidden visibility, so that it is not
//! exported from the FMUs' library and its callers bind to it at link time: nothing is looked up
//! at load time, so no host libm can interpose.
//!
//! Arguments and results are those of C's `<math.h>` (radians for angles); the functions are
//! pure, they never panic.
//!
//! Built for x86_64 Linux, x86_64 Windows and aarch64 Linux (the platforms of
//! [`super::platform`]); elsewhere the module is left out and build.rs wraps nothing.

#[path = "c_math_symbols.rs"]
mod symbols;
pub use symbols::{WRAPPED, WRAPPED_WINDOWS};

/// `__wrap_<name>`: a tail jump to the Rust function `$f` (same C signature as `<name>`).
macro_rules! trampoline {
    ($name:ident, $f:path) => {
        #[cfg(all(target_arch = "x86_64", target_os = "linux"))]
        core::arch::global_asm!(
            concat!(".pushsection .text.__wrap_", stringify!($name), ",\"ax\",@progbits"),
            concat!(".globl __wrap_", stringify!($name)),
            concat!(".hidden __wrap_", stringify!($name)),
            concat!(".type __wrap_", stringify!($name), ",@function"),
            ".p2align 4",
            concat!("__wrap_", stringify!($name), ":"),
            "jmp {f}",
            concat!(".size __wrap_", stringify!($name), ", . - __wrap_", stringify!($name)),
            ".popsection",
            f = sym $f,
        );
        #[cfg(all(target_arch = "aarch64", target_os = "linux"))]
        core::arch::global_asm!(
            concat!(".pushsection .text.__wrap_", stringify!($name), ",\"ax\",%progbits"),
            concat!(".globl __wrap_", stringify!($name)),
            concat!(".hidden __wrap_", stringify!($name)),
            concat!(".type __wrap_", stringify!($name), ",%function"),
            ".p2align 2",
            concat!("__wrap_", stringify!($name), ":"),
            "b {f}",
            concat!(".size __wrap_", stringify!($name), ", . - __wrap_", stringify!($name)),
            ".popsection",
            f = sym $f,
        );
        // PE/COFF: a DLL exports only what its .def file lists (rustc writes it), so the
        // symbol needs no visibility.
        #[cfg(all(target_arch = "x86_64", target_os = "windows"))]
        core::arch::global_asm!(
            ".text",
            concat!(".globl __wrap_", stringify!($name)),
            ".p2align 4",
            concat!("__wrap_", stringify!($name), ":"),
            "jmp {f}",
            f = sym $f,
        );
    };
}

/// For each `name(args): T = body;`: the Rust function `name` (C ABI, arguments and result of
/// type `T`) computing `body`, its trampoline `__wrap_name`, and the name in [`DEFINED`].
macro_rules! wrap {
    ($($name:ident($($arg:ident),+): $t:ty = $body:expr;)*) => {
        $(
            extern "C" fn $name($($arg: $t),+) -> $t {
                $body
            }
            trampoline!($name, $name);
        )*
        /// The names this module defines `__wrap_<name>` for, on every platform.
        pub const DEFINED: &[&str] = &[$(stringify!($name),)* "sincos", "sincosf"];
    };
}

wrap! {
    acos(x): f64 = libm::acos(x);
    asin(x): f64 = libm::asin(x);
    atan(x): f64 = libm::atan(x);
    atan2(y, x): f64 = libm::atan2(y, x);
    cbrt(x): f64 = libm::cbrt(x);
    ceil(x): f64 = libm::ceil(x);
    cos(x): f64 = libm::cos(x);
    cosh(x): f64 = libm::cosh(x);
    exp(x): f64 = libm::exp(x);
    exp2(x): f64 = libm::exp2(x);
    expm1(x): f64 = libm::expm1(x);
    floor(x): f64 = libm::floor(x);
    fmod(x, y): f64 = libm::fmod(x, y);
    hypot(x, y): f64 = libm::hypot(x, y);
    log(x): f64 = libm::log(x);
    log10(x): f64 = libm::log10(x);
    log1p(x): f64 = libm::log1p(x);
    log2(x): f64 = libm::log2(x);
    pow(x, y): f64 = libm::pow(x, y);
    round(x): f64 = libm::round(x);
    sin(x): f64 = libm::sin(x);
    sinh(x): f64 = libm::sinh(x);
    tan(x): f64 = libm::tan(x);
    tanh(x): f64 = libm::tanh(x);
    trunc(x): f64 = libm::trunc(x);
    acosf(x): f32 = libm::acosf(x);
    atan2f(y, x): f32 = libm::atan2f(y, x);
    cosf(x): f32 = libm::cosf(x);
    powf(x, y): f32 = libm::powf(x, y);
    sinf(x): f32 = libm::sinf(x);
}

/// C's `sincos`: `*s = sin(x)`, `*c = cos(x)`. LLVM merges `x.sin()` and `x.cos()` into one
/// call of it where the C runtime has one (glibc, mingw-w64); computed as the two separate
/// functions, so that the bits do not depend on whether the merge happened.
///
/// # Safety
/// `s` and `c` point to writable `f64`s (C's contract; LLVM passes stack slots).
unsafe extern "C" fn sincos(x: f64, s: *mut f64, c: *mut f64) {
    // SAFETY: the caller's contract above.
    unsafe {
        s.write(libm::sin(x));
        c.write(libm::cos(x));
    }
}
trampoline!(sincos, sincos);

/// C's `sincosf`, as [`sincos`] for `f32`.
///
/// # Safety
/// `s` and `c` point to writable `f32`s.
unsafe extern "C" fn sincosf(x: f32, s: *mut f32, c: *mut f32) {
    // SAFETY: the caller's contract above.
    unsafe {
        s.write(libm::sinf(x));
        c.write(libm::cosf(x));
    }
}
trampoline!(sincosf, sincosf);

/// msvcrt's name of `hypot`, which Rust's standard library calls on Windows.
#[cfg(target_os = "windows")]
extern "C" fn hypot_msvcrt(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}
#[cfg(target_os = "windows")]
trampoline!(_hypot, hypot_msvcrt);

#[cfg(test)]
mod tests {
    use super::*;
    use std::hint::black_box;

    #[test]
    fn every_wrapped_name_is_defined() {
        let mut wrapped = WRAPPED.to_vec();
        let mut defined = DEFINED.to_vec();
        wrapped.sort_unstable();
        defined.sort_unstable();
        assert_eq!(wrapped, defined);
        assert_eq!(WRAPPED_WINDOWS, ["_hypot"]);
    }

    /// Per function, an argument where glibc 2.36's result (Python's `math` on this machine,
    /// 2026-12-07) differs from the `libm` crate's in the last bit, and glibc's bits.
    const GLIBC_DIFFERS: [(&str, &[f64], u64); 20] = [
        ("acos", &[0.6041754925033666], 0x3fed818fa8e44786),
        ("asin", &[0.5357142213619858], 0x3fe2175feac74cbf),
        ("atan", &[3.9348987272277824], 0x3ff5269ea10c5077),
        (
            "atan2",
            &[7.19588241561633, -0.10569866164366326],
            0x3ff95e2483647c97,
        ),
        ("cbrt", &[29.514483359709605], 0x4008b918913a74e4),
        ("cos", &[5.6011479397551645], 0x3fe8d75e2cd8c01f),
        ("cosh", &[-6.490756419338675], 0x4074982f7da4a920),
        ("exp", &[-9.300397635799367], 0x3f17f4efe9797873),
        ("exp2", &[-5.368195937959639], 0x3f98cac1fbeca7b9),
        ("expm1", &[-0.5160811299064405], 0xbfd9cd20d21461a9),
        (
            "hypot",
            &[-9.300397635799367, 9.126760726776201],
            0x402a0fa3de5c7755,
        ),
        ("log", &[2.7686120627453246], 0x3ff04b2550e97fe5),
        ("log10", &[4.631066256406797], 0x3fe54d423a99825c),
        ("log1p", &[0.5230770377037852], 0x3fdaed48a8ee8f24),
        ("log2", &[40.698392119812794], 0x40156339b9c8ab73),
        (
            "pow",
            &[36.77327245312969, -3.0004315898040375],
            0x3ef50dbc086309b1,
        ),
        ("sin", &[-5.840763782653449], 0x3fdb667790a5476d),
        ("sinh", &[-1.6749419156156642], 0xc0049acb426637ea),
        ("tan", &[-0.4078487146034804], 0xbfdba721bfba671b),
        ("tanh", &[0.5239013638807133], 0x3fdec3e0e9aceca9),
    ];

    /// (std's result, the `libm` crate's) for `name` at `a`.
    fn both(name: &str, a: &[f64]) -> (f64, f64) {
        let x = black_box(a[0]);
        let y = black_box(a.get(1).copied().unwrap_or(0.0));
        match name {
            "acos" => (x.acos(), libm::acos(x)),
            "asin" => (x.asin(), libm::asin(x)),
            "atan" => (x.atan(), libm::atan(x)),
            "atan2" => (x.atan2(y), libm::atan2(x, y)),
            "cbrt" => (x.cbrt(), libm::cbrt(x)),
            "cos" => (x.cos(), libm::cos(x)),
            "cosh" => (x.cosh(), libm::cosh(x)),
            "exp" => (x.exp(), libm::exp(x)),
            "exp2" => (x.exp2(), libm::exp2(x)),
            "expm1" => (x.exp_m1(), libm::expm1(x)),
            "hypot" => (x.hypot(y), libm::hypot(x, y)),
            "log" => (x.ln(), libm::log(x)),
            "log10" => (x.log10(), libm::log10(x)),
            "log1p" => (x.ln_1p(), libm::log1p(x)),
            "log2" => (x.log2(), libm::log2(x)),
            "pow" => (x.powf(y), libm::pow(x, y)),
            "sin" => (x.sin(), libm::sin(x)),
            "sinh" => (x.sinh(), libm::sinh(x)),
            "tan" => (x.tan(), libm::tan(x)),
            "tanh" => (x.tanh(), libm::tanh(x)),
            _ => panic!("no case for {name}"),
        }
    }

    /// This test binary is linked like every artifact: std's `f64` functions give the `libm`
    /// crate's bits, at arguments where glibc's differ (so the test fails if the wrapping is
    /// lost and glibc is called again).
    #[test]
    fn std_math_is_the_libm_crate() {
        for (name, args, glibc) in GLIBC_DIFFERS {
            let (std, pure) = both(name, args);
            assert_eq!(
                std.to_bits(),
                pure.to_bits(),
                "{name}{args:?}: std {std:e}, libm {pure:e}"
            );
            assert_ne!(
                pure.to_bits(),
                glibc,
                "{name}{args:?}: no longer tells libm from glibc"
            );
        }
        // `sin` and `cos` of one argument (LLVM's `sincos`), where glibc's `sin` differs; `%`
        // (`fmod`) and the rounding functions are exact in every libm: here only that each
        // wrapper calls the right function
        let x = black_box(-5.840763782653449_f64);
        assert_eq!((x.sin(), x.cos()), (libm::sin(x), libm::cos(x)));
        let (a, b) = black_box((7.25_f64, 0.7));
        assert_eq!((a % b).to_bits(), libm::fmod(a, b).to_bits());
        let y = black_box(-2.5_f64);
        assert_eq!(
            [y.floor(), y.ceil(), y.round(), y.trunc()],
            [-3.0, -2.0, -3.0, -2.0]
        );
    }
}
