//! FMUs packed around the cdylib that `cargo test` has just built next to the test executable
//! (`target/<profile>/deps/libmbcosim.so`), so importer tests check the current sources.

use std::path::PathBuf;

use mbcosim::fmi::package::{self, Binary};
use mbcosim::fmi::platform::Platform;
use mbcosim::scene;

/// Which FMI version to pack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fmi {
    V2,
    V3,
}

/// The FMU of model `identifier` packed into a temporary folder named after `tag` and this
/// process; returns its path.
pub fn packed(identifier: &str, version: Fmi, tag: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let lib = [
        deps.join("libmbcosim.so"),
        deps.parent().unwrap().join("libmbcosim.so"),
    ]
    .into_iter()
    .find(|p| p.is_file())
    .expect("libmbcosim.so next to the test executable (cargo builds the cdylib with the rlib)");
    let out =
        std::env::temp_dir().join(format!("mbcosim-{tag}-{}-{identifier}", std::process::id()));
    let entry = scene::find_by_identifier(identifier).unwrap();
    let md = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("modelDescription");
    // the host's library only: these tests load it in this process
    let lib = [Binary {
        platform: Platform::LinuxX86_64,
        path: lib,
    }];
    match version {
        Fmi::V2 => package::pack(&entry, &lib, &md, &out, None),
        Fmi::V3 => package::pack3(&entry, &lib, &md, &out, None),
    }
    .unwrap()
}
