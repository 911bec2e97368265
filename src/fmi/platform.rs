//! The platforms the FMUs ship a binary for, and where each binary goes in the archive.
//!
//! One table: the Rust target triple that builds the library, the folder under `binaries/` in
//! FMI 2.0 and FMI 3.0, and the library's file names. FMI 2.0 names only x86 platforms
//! (`win64`, `linux64`, `darwin64`, ...): `linux64` means x86_64 Linux, so the aarch64 Linux
//! binary of an FMI 2.0 FMU goes under the FMI 3.0 platform tuple `aarch64-linux`
//! (docs/platforms.md gives the reasons). macOS is not built: it cannot be executed here, and
//! nothing ships that was not run (README, docs/platforms.md).

/// A platform with a binary in every FMU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Platform {
    /// x86_64 Linux, glibc 2.17 or newer.
    LinuxX86_64,
    /// x86_64 Windows (64-bit), Windows 10 or newer.
    WindowsX86_64,
    /// aarch64 (ARM64) Linux, glibc 2.17 or newer.
    LinuxAarch64,
}

impl Platform {
    /// Every platform, in the order the archive lists them.
    pub const ALL: [Platform; 3] = [
        Platform::LinuxX86_64,
        Platform::WindowsX86_64,
        Platform::LinuxAarch64,
    ];

    /// The FMI 3.0 platform tuple, also the name `--platforms` takes.
    pub fn tuple(self) -> &'static str {
        match self {
            Platform::LinuxX86_64 => "x86_64-linux",
            Platform::WindowsX86_64 => "x86_64-windows",
            Platform::LinuxAarch64 => "aarch64-linux",
        }
    }

    /// The folder under `binaries/` of an FMI 2.0 FMU.
    pub fn fmi2_folder(self) -> &'static str {
        match self {
            Platform::LinuxX86_64 => "linux64",
            Platform::WindowsX86_64 => "win64",
            // FMI 2.0 has no name for it; `linux64` is x86_64 (docs/platforms.md)
            Platform::LinuxAarch64 => "aarch64-linux",
        }
    }

    /// The folder under `binaries/` of an FMI 3.0 FMU.
    pub fn fmi3_folder(self) -> &'static str {
        self.tuple()
    }

    /// The Rust target triple the library is built for.
    pub fn rust_target(self) -> &'static str {
        match self {
            Platform::LinuxX86_64 => "x86_64-unknown-linux-gnu",
            Platform::WindowsX86_64 => "x86_64-pc-windows-gnu",
            Platform::LinuxAarch64 => "aarch64-unknown-linux-gnu",
        }
    }

    /// The file name extension of a shared library there (`so`, `dll`).
    pub fn extension(self) -> &'static str {
        match self {
            Platform::WindowsX86_64 => "dll",
            Platform::LinuxX86_64 | Platform::LinuxAarch64 => "so",
        }
    }

    /// The platform whose FMI 3.0 tuple is `name`, or why there is none.
    pub fn parse(name: &str) -> Result<Platform, String> {
        Platform::ALL
            .into_iter()
            .find(|p| p.tuple() == name)
            .ok_or_else(|| {
                let known: Vec<&str> = Platform::ALL.iter().map(|p| p.tuple()).collect();
                format!(
                    "unknown platform `{}`: the FMUs can carry {}",
                    name.escape_debug(),
                    known.join(", ")
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_follow_fmi2_and_fmi3_names() {
        let rows: Vec<_> = Platform::ALL
            .iter()
            .map(|p| (p.fmi2_folder(), p.fmi3_folder(), p.extension()))
            .collect();
        assert_eq!(
            rows,
            [
                ("linux64", "x86_64-linux", "so"),
                ("win64", "x86_64-windows", "dll"),
                ("aarch64-linux", "aarch64-linux", "so"),
            ]
        );
        for p in Platform::ALL {
            assert_eq!(Platform::parse(p.tuple()), Ok(p));
        }
        let e = Platform::parse("x86_64-darwin").unwrap_err();
        assert!(
            e.contains("x86_64-darwin") && e.contains("aarch64-linux"),
            "{e}"
        );
    }
}
