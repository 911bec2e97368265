// The C math functions that every artifact of this crate takes from `c_math` (pure Rust, the
// `libm` crate) instead of the C runtime: the Windows DLL, the Linux and aarch64 libraries, the
// executables, the test binaries (docs/platforms.md, "One libm in every artifact").
//
// Shared by build.rs (which passes `-Wl,-wrap,NAME` for each to the linker, so that every
// reference to NAME in any object file of the link resolves to `__wrap_NAME`) and by
// src/fmi/c_math.rs (which defines `__wrap_NAME`; a unit test there checks that both agree).
// Plain Rust without attributes, so that build.rs can `include!` it.

/// Every C symbol redirected to `__wrap_<name>` on every platform: the union of the math
/// functions that the x86_64 Linux library, executables, test binaries and examples and the
/// Windows DLL referenced before the change (their undefined symbols, 2026-12-07: the `f32` ones
/// come from glam and num-traits, `floor` ... `trunc` and `sincos` also from parry and our
/// code, on Windows from msvcrt.dll and mingw-w64's static libmingwex, on Linux from Rust's
/// compiler-builtins), and `atan`, `cbrt`, `exp2` and `fmod`, which std reaches through
/// `f64::atan`, `cbrt`, `exp2` and `%`.
pub const WRAPPED: [&str; 32] = [
    "acos", "asin", "atan", "atan2", "cbrt", "ceil", "cos", "cosh", "exp", "exp2", "expm1",
    "floor", "fmod", "hypot", "log", "log10", "log1p", "log2", "pow", "round", "sin", "sincos",
    "sinh", "tan", "tanh", "trunc", "acosf", "atan2f", "cosf", "powf", "sincosf", "sinf",
];

/// Redirected on Windows only: Rust's standard library calls msvcrt's `_hypot` for `f64::hypot`.
pub const WRAPPED_WINDOWS: [&str; 1] = ["_hypot"];
