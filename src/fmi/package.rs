//! Builds `.fmu` archives: one zip per registered model around the same shared library.
//!
//! Layout of `<Identifier>.fmu` (FMI 2.0, [`pack`]) and `fmi3/<Identifier>.fmu` (FMI 3.0,
//! [`pack3`], its description from `modelDescription/fmi3/`):
//!
//! ```text
//! modelDescription.xml              the checked-in modelDescription/<Identifier>.xml
//! binaries/linux64/<Identifier>.so  the crate's cdylib for each platform, renamed (no `lib`
//! binaries/win64/<Identifier>.dll   prefix); FMI 3.0: x86_64-linux, x86_64-windows,
//! binaries/aarch64-linux/<Identifier>.so   aarch64-linux ([`Platform`], docs/platforms.md)
//! documentation/index.html          generated from the variable table
//! documentation/licenses/license.txt the licence (the repository's LICENSE)
//! resources/scene.toml               the default scene (parameters), read at instantiation
//! resources/...                     the model's data files, when it has any
//! ```
//!
//! Beside each archive, for a model with power ports: `<Identifier>_OspModelDescription.xml`,
//! its OSP-IS port file ([`super::osp`]), where libcosim looks for it.
//!
//! The archive is reproducible: entries in a fixed order with a fixed 1980-01-01 timestamp, and
//! the description's `generationDateAndTime` is the time the caller passes (the commit time,
//! [`super::metadata`]), never the clock.
//! Packing refuses a checked-in description that differs from the one the table produces, so a
//! stale GUID or variable list can never ship.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

use super::platform::Platform;
use super::{documentation, metadata, model_description, model_description3};
use crate::scene::ModelEntry;

/// Where the checked-in description of `identifier` lives under `dir` (`modelDescription/`).
pub fn description_path(dir: &Path, identifier: &str) -> PathBuf {
    dir.join(format!("{identifier}.xml"))
}

/// The command that rewrites the checked-in descriptions from the tables.
pub const REGENERATE: &str = "cargo run --release --bin mbcosim -- model-descriptions";

/// Reads the checked-in description of `entry` and checks that it matches the table.
pub fn checked_description(entry: &ModelEntry, descriptions: &Path) -> Result<String, String> {
    let info = (entry.info)();
    let path = description_path(descriptions, info.identifier);
    let on_disk =
        fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let generated = model_description::write(info)?;
    if on_disk != generated {
        return Err(format!(
            "{} differs from the variable table of {}; regenerate it with `{REGENERATE}` (and change the GUID if the variables changed)",
            path.display(),
            info.identifier
        ));
    }
    Ok(on_disk)
}

/// The crate's shared library built for one platform.
#[derive(Debug, Clone)]
pub struct Binary {
    pub platform: Platform,
    /// The built library (`libmbcosim.so`, `mbcosim.dll`).
    pub path: PathBuf,
}

/// Writes `<out_dir>/<Identifier>.fmu` for `entry` with `binaries` (one per platform); returns
/// its path. `generated_at` (an `xs:dateTime`, the commit time) becomes the description's
/// `generationDateAndTime`; `None` leaves the attribute out.
pub fn pack(
    entry: &ModelEntry,
    binaries: &[Binary],
    descriptions: &Path,
    out_dir: &Path,
    generated_at: Option<&str>,
) -> Result<PathBuf, String> {
    let xml = stamped(checked_description(entry, descriptions)?, generated_at)?;
    let folders: Vec<&str> = binaries.iter().map(|b| b.platform.fmi2_folder()).collect();
    let page = documentation::index_html((entry.info)(), &folders);
    write_fmu(entry, binaries, Platform::fmi2_folder, xml, page, out_dir)
}

/// Where the checked-in FMI 3.0 description of `identifier` lives under `dir`
/// (`modelDescription/fmi3/`).
pub fn description_path3(dir: &Path, identifier: &str) -> PathBuf {
    dir.join("fmi3").join(format!("{identifier}.xml"))
}

/// Reads the checked-in FMI 3.0 description of `entry` and checks that it matches the table.
pub fn checked_description3(entry: &ModelEntry, descriptions: &Path) -> Result<String, String> {
    let info = (entry.info)();
    let path = description_path3(descriptions, info.identifier);
    let on_disk =
        fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if on_disk != model_description3::write(info)? {
        return Err(format!(
            "{} differs from the variable table of {}; regenerate it with `{REGENERATE}` (and change the GUID if the variables changed)",
            path.display(),
            info.identifier
        ));
    }
    Ok(on_disk)
}

/// Writes the FMI 3.0 FMU `<out_dir>/<Identifier>.fmu` for `entry` (the same libraries, under
/// the FMI 3.0 platform tuples `binaries/x86_64-linux/` ...); returns its path. `generated_at`
/// as for [`pack`].
pub fn pack3(
    entry: &ModelEntry,
    binaries: &[Binary],
    descriptions: &Path,
    out_dir: &Path,
    generated_at: Option<&str>,
) -> Result<PathBuf, String> {
    let xml = stamped(checked_description3(entry, descriptions)?, generated_at)?;
    let folders: Vec<&str> = binaries.iter().map(|b| b.platform.fmi3_folder()).collect();
    let page = documentation::index_html3((entry.info)(), &folders);
    write_fmu(entry, binaries, Platform::fmi3_folder, xml, page, out_dir)
}

/// `xml` with `generationDateAndTime` when a time is given.
fn stamped(xml: String, generated_at: Option<&str>) -> Result<String, String> {
    match generated_at {
        Some(when) => metadata::stamp_generation_time(&xml, when),
        None => Ok(xml),
    }
}

/// The archive: `folder` names each binary's folder under `binaries/` (FMI 2.0 or 3.0 names).
fn write_fmu(
    entry: &ModelEntry,
    binaries: &[Binary],
    folder: fn(Platform) -> &'static str,
    xml: String,
    page: String,
    out_dir: &Path,
) -> Result<PathBuf, String> {
    let info = (entry.info)();
    if binaries.is_empty() {
        return Err(format!("{}: no binary to pack", info.identifier));
    }
    fs::create_dir_all(out_dir).map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let target = out_dir.join(format!("{}.fmu", info.identifier));
    let partial = out_dir.join(format!(".{}.fmu.partial", info.identifier));
    let io = |e: std::io::Error| format!("writing {}: {e}", partial.display());
    let zerr = |e: zip::result::ZipError| format!("writing {}: {e}", partial.display());
    let file = fs::File::create(&partial).map_err(io)?;
    let mut zip = ZipWriter::new(file);
    let opts = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(DateTime::default())
        .unix_permissions(0o644);
    let mut entries: Vec<(String, Vec<u8>, u32)> =
        vec![("modelDescription.xml".into(), xml.into_bytes(), 0o644)];
    for b in binaries {
        let bytes = fs::read(&b.path)
            .map_err(|e| format!("cannot read the shared library {}: {e}", b.path.display()))?;
        let name = format!(
            "binaries/{}/{}.{}",
            folder(b.platform),
            info.identifier,
            b.platform.extension()
        );
        entries.push((name, bytes, 0o755));
    }
    entries.extend([
        ("documentation/index.html".into(), page.into_bytes(), 0o644),
        (
            metadata::LICENSE_ENTRY.into(),
            metadata::LICENSE_TEXT.as_bytes().to_vec(),
            0o644,
        ),
        (
            format!("resources/{}", crate::scene::scene_file::FMU_SCENE),
            crate::scene::scene_file::render(info).into_bytes(),
            0o644,
        ),
    ]);
    for r in entry.resources {
        if r.path
            .split('/')
            .any(|c| c.is_empty() || c == "." || c == "..")
        {
            return Err(format!(
                "resource path `{}` of {} must be relative and plain",
                r.path, info.identifier
            ));
        }
        entries.push((format!("resources/{}", r.path), r.bytes.to_vec(), 0o644));
    }
    for (name, bytes, mode) in &entries {
        zip.start_file(name.as_str(), opts.unix_permissions(*mode))
            .map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    zip.finish().map_err(zerr)?.sync_all().map_err(io)?;
    fs::rename(&partial, &target).map_err(|e| format!("renaming to {}: {e}", target.display()))?;
    // the OSP-IS port file beside the FMU, where libcosim looks for it (docs/osp_ports.md)
    if let Some(ports) = super::osp::write(entry)? {
        let path = out_dir.join(super::osp::file_name(info.identifier));
        fs::write(&path, ports).map_err(|e| format!("writing {}: {e}", path.display()))?;
    }
    Ok(target)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Resource, pid};
    use std::io::Read;

    #[test]
    fn fmu_layout_and_stale_description_refusal() {
        let dir = std::env::temp_dir().join(format!("mbcosim-pack-{}", std::process::id()));
        let descr = dir.join("md");
        fs::create_dir_all(&descr).unwrap();
        let binaries: Vec<Binary> = Platform::ALL
            .iter()
            .map(|&platform| {
                let path = dir.join(format!("fake-{}", platform.tuple()));
                fs::write(&path, format!("fake {}", platform.tuple())).unwrap();
                Binary { platform, path }
            })
            .collect();
        const RES: &[Resource] = &[Resource {
            path: "data/table.csv",
            bytes: b"a,b\n1,2\n",
        }];
        let entry = ModelEntry::new(pid::info, pid::create).with_resources(RES);

        fs::write(description_path(&descr, "PidController"), "<stale/>").unwrap();
        let e = pack(&entry, &binaries, &descr, &dir, None).unwrap_err();
        assert!(e.contains(REGENERATE), "{e}");

        fs::write(
            description_path(&descr, "PidController"),
            model_description::write(pid::info()).unwrap(),
        )
        .unwrap();
        let when = "2026-12-07T05:30:45Z";
        let fmu = pack(&entry, &binaries, &descr, &dir, Some(when)).unwrap();
        let mut z = zip::ZipArchive::new(fs::File::open(&fmu).unwrap()).unwrap();
        let names: Vec<String> = z.file_names().map(|n| n.unwrap().into_owned()).collect();
        for n in [
            "modelDescription.xml",
            "documentation/index.html",
            metadata::LICENSE_ENTRY,
            "resources/data/table.csv",
        ] {
            assert!(names.iter().any(|x| x == n), "{n} in {names:?}");
        }
        let libs: Vec<&String> = names
            .iter()
            .filter(|n| n.starts_with("binaries/"))
            .collect();
        assert_eq!(
            libs,
            [
                "binaries/linux64/PidController.so",
                "binaries/win64/PidController.dll",
                "binaries/aarch64-linux/PidController.so",
            ]
        );
        for (name, tuple) in [
            ("binaries/linux64/PidController.so", "x86_64-linux"),
            ("binaries/win64/PidController.dll", "x86_64-windows"),
            ("binaries/aarch64-linux/PidController.so", "aarch64-linux"),
        ] {
            let mut so = String::new();
            z.by_name(name).unwrap().read_to_string(&mut so).unwrap();
            assert_eq!(so, format!("fake {tuple}"));
        }
        let first = fs::read(&fmu).unwrap();
        let mut xml = String::new();
        z.by_name("modelDescription.xml")
            .unwrap()
            .read_to_string(&mut xml)
            .unwrap();
        assert!(
            xml.contains(&format!("generationDateAndTime=\"{when}\"")),
            "{xml}"
        );
        let mut license = String::new();
        z.by_name(metadata::LICENSE_ENTRY)
            .unwrap()
            .read_to_string(&mut license)
            .unwrap();
        assert!(license.starts_with("MIT License"), "{license}");
        let again = pack(&entry, &binaries, &descr, &dir, Some(when)).unwrap();
        assert_eq!(fs::read(again).unwrap(), first, "reproducible archive");
        assert!(
            pack(&entry, &[], &descr, &dir, Some(when))
                .unwrap_err()
                .contains("no binary")
        );
        fs::remove_dir_all(&dir).unwrap();
    }
}
