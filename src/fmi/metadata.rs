//! Who made an FMU, under which licence, with which tool and when: the attributes every
//! `fmiModelDescription` carries (FMI 2.0 and 3.0 alike) and the licence text packed into each
//! FMU's `documentation/licenses/` (docs/fmu_metadata.md).
//!
//! `generationDateAndTime` is not in the checked-in descriptions (it would change with every
//! commit): [`stamp_generation_time`] adds it at packing time from the commit time, so two packs
//! of one commit are byte-identical.

/// Name written to `generationTool`: the crate and its version.
pub const GENERATION_TOOL: &str = concat!("mbcosim ", env!("CARGO_PKG_VERSION"));

/// `version` of every model: the crate's version (all models ship together).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// `author` of every model.
pub const AUTHOR: &str = "The mbcosim developers";

/// `copyright` of every model.
pub const COPYRIGHT: &str = "Copyright (c) 2026 The mbcosim developers";

/// `license` of every model: the SPDX identifier and where the full text is.
pub const LICENSE: &str = "MIT (documentation/licenses/license.txt)";

/// The full licence text (the repository's `LICENSE`).
pub const LICENSE_TEXT: &str = include_str!("../../LICENSE");

/// Where [`LICENSE_TEXT`] is packed in an FMU (FMI 3.0's `documentation/licenses/` folder; the
/// FMI 2.0 FMUs use the same path).
pub const LICENSE_ENTRY: &str = "documentation/licenses/license.txt";

/// The metadata attributes in the order the FMI schemas list them, between `description` and
/// `generationTool`.
pub fn attributes() -> [(&'static str, String); 4] {
    [
        ("author", AUTHOR.to_string()),
        ("version", VERSION.to_string()),
        ("copyright", COPYRIGHT.to_string()),
        ("license", LICENSE.to_string()),
    ]
}

/// `xml` (a description from the tables) with `generationDateAndTime="<when>"` right after its
/// `generationTool` attribute; `when` is an `xs:dateTime`. Errors when the description has no
/// `generationTool` attribute or already carries a generation time.
pub fn stamp_generation_time(xml: &str, when: &str) -> Result<String, String> {
    let tool = format!("generationTool=\"{GENERATION_TOOL}\"");
    if xml.contains("generationDateAndTime=") {
        return Err("the description already carries generationDateAndTime".into());
    }
    let at = xml
        .find(&tool)
        .ok_or_else(|| format!("the description has no {tool} attribute"))?
        + tool.len();
    Ok(format!(
        "{} generationDateAndTime=\"{when}\"{}",
        &xml[..at],
        &xml[at..]
    ))
}

/// `seconds` since 1970-01-01T00:00:00Z (a commit time or `SOURCE_DATE_EPOCH`) as the UTC
/// `xs:dateTime` `YYYY-MM-DDThh:mm:ssZ`. Errors for times before 1970 or after 9999.
pub fn utc_date_time(seconds: i64) -> Result<String, String> {
    if !(0..=253_402_300_799).contains(&seconds) {
        return Err(format!(
            "time {seconds} s since 1970 is outside 1970-01-01 .. 9999-12-31"
        ));
    }
    let (days, secs) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    Ok(format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs / 60 % 60,
        secs % 60
    ))
}

/// Proleptic Gregorian (year, month, day) of `days` since 1970-01-01: eras of 400 years
/// (146,097 days) counted from 0000-03-01, so that the leap day ends each year of the era.
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468; // days since 0000-03-01
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // day of the era [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // year of the era
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // day of the year from March 1
    let mp = (5 * doy + 2) / 153; // month from March = 0
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_against_known_calendar_days() {
        // independent values: `date -u -d @N` of GNU coreutils
        assert_eq!(utc_date_time(0).unwrap(), "1970-01-01T00:00:00Z");
        assert_eq!(utc_date_time(951_782_400).unwrap(), "2000-02-29T00:00:00Z");
        assert_eq!(
            utc_date_time(1_709_164_799).unwrap(),
            "2024-02-28T23:59:59Z"
        );
        assert_eq!(
            utc_date_time(1_709_251_200).unwrap(),
            "2024-03-01T00:00:00Z"
        );
        assert_eq!(
            utc_date_time(1_796_621_445).unwrap(),
            "2026-12-07T05:30:45Z"
        );
        assert_eq!(
            utc_date_time(4_107_542_400).unwrap(),
            "2100-03-01T00:00:00Z"
        );
        assert_eq!(
            utc_date_time(253_402_300_799).unwrap(),
            "9999-12-31T23:59:59Z"
        );
        assert!(utc_date_time(-1).unwrap_err().contains("outside"));
        assert!(utc_date_time(253_402_300_800).is_err());
    }

    #[test]
    fn generation_time_goes_after_the_tool_once() {
        let xml =
            format!("<fmiModelDescription a=\"1\" generationTool=\"{GENERATION_TOOL}\" b=\"2\">");
        let stamped = stamp_generation_time(&xml, "2026-12-07T05:30:45Z").unwrap();
        assert_eq!(
            stamped,
            format!(
                "<fmiModelDescription a=\"1\" generationTool=\"{GENERATION_TOOL}\" generationDateAndTime=\"2026-12-07T05:30:45Z\" b=\"2\">"
            )
        );
        assert!(stamp_generation_time(&stamped, "x").is_err());
        assert!(stamp_generation_time("<a/>", "x").is_err());
    }
}
