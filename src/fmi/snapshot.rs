//! FMU states: a copy of the model plus the wrapper's state-machine data, and their bytes.
//!
//! Serialized format, version 1 (all little-endian, see [`crate::scene::bytes`]):
//!
//! | field                     | encoding                                   |
//! |---------------------------|--------------------------------------------|
//! | magic                     | 8 bytes `MBCSFMU2`                         |
//! | format version            | `u32` = 1                                  |
//! | model identifier, GUID    | two length-prefixed UTF-8 strings          |
//! | instance state            | `u32` state code (never `fatal`)           |
//! | start time [s]            | `f64`                                      |
//! | stop time [s], tolerance  | `bool` defined + `f64` each                |
//! | last successful time [s]  | `f64`                                      |
//! | model state               | length-prefixed bytes of `CoSimModel::serialize` |
//! | checksum                  | `u64` FNV-1a of every byte before it       |
//!
//! Bytes that are truncated, altered, from another model or from another format version are
//! refused with a message saying which; no pointer is ever stored.

use super::machine::{Machine, State};
use std::path::Path;

use crate::scene::bytes::{ByteReader, ByteWriter, FieldSpan, checksum64, trace_fields};
use crate::scene::{CoSimModel, ModelError, find_by_identifier};

/// Leading bytes of every serialized FMU state.
pub const MAGIC: &[u8; 8] = b"MBCSFMU2";
/// Current (and highest readable) format version.
pub const FORMAT_VERSION: u32 = 1;

/// One saved FMU state (what an `fmi2FMUstate` handle points to).
pub struct Snapshot {
    /// State-machine data at the time of saving.
    pub machine: Machine,
    /// A full copy of the model.
    pub model: Box<dyn CoSimModel>,
    /// Serialized bytes, computed on first request.
    bytes: Option<Vec<u8>>,
}

impl Snapshot {
    /// A snapshot of `model` and `machine`.
    pub fn new(machine: Machine, model: Box<dyn CoSimModel>) -> Self {
        Self {
            machine,
            model,
            bytes: None,
        }
    }

    /// The serialized bytes (computed once, then cached).
    pub fn bytes(&mut self) -> &[u8] {
        let (machine, model) = (&self.machine, &self.model);
        self.bytes
            .get_or_insert_with(|| encode(machine, model.as_ref()))
    }
}

fn encode(m: &Machine, model: &dyn CoSimModel) -> Vec<u8> {
    let info = model.info();
    let mut w = ByteWriter::new();
    w.raw(MAGIC);
    w.u32(FORMAT_VERSION);
    w.str(info.identifier);
    w.str(info.guid);
    w.u32(m.state.code());
    w.f64(m.start_time);
    for opt in [m.stop_time, m.tolerance] {
        w.bool(opt.is_some());
        w.f64(opt.unwrap_or(0.0));
    }
    w.f64(m.last_successful_time);
    w.bytes(&model.serialize());
    let sum = checksum64(w.as_bytes());
    w.u64(sum);
    w.into_bytes()
}

/// Restores a snapshot from `bytes` into a fresh model made by `create` (which also tells it
/// where its resources are, so states naming relative data files restore).
pub fn decode(
    bytes: &[u8],
    create: &dyn Fn() -> Box<dyn CoSimModel>,
) -> Result<Snapshot, ModelError> {
    let bad = |m: String| ModelError::BadState(m);
    let mut r = ByteReader::new(bytes);
    r.expect_raw(MAGIC, "magic bytes (not an mbcosim FMU state)")?;
    let version = r.u32("format version")?;
    if version != FORMAT_VERSION {
        return Err(bad(format!(
            "FMU state format version {version} is not supported (this build reads version {FORMAT_VERSION})"
        )));
    }
    if bytes.len() < MAGIC.len() + 4 + 8 {
        return Err(bad(format!("truncated FMU state: {} bytes", bytes.len())));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    let stored = u64::from_le_bytes(
        sum.try_into()
            .map_err(|_| bad("truncated checksum".into()))?,
    );
    if checksum64(body) != stored {
        return Err(bad(format!(
            "corrupt or truncated FMU state: checksum mismatch over {} bytes",
            body.len()
        )));
    }
    let mut model = create();
    let info = model.info();
    let ident = r.str("model identifier")?;
    let guid = r.str("GUID")?;
    if ident != info.identifier || guid != info.guid {
        return Err(bad(format!(
            "FMU state belongs to model `{}` (GUID {}), not to `{}` (GUID {})",
            ident.escape_debug(),
            guid.escape_debug(),
            info.identifier,
            info.guid
        )));
    }
    let code = r.u32("instance state")?;
    let state = match State::from_code(code) {
        Some(State::Fatal) | None => {
            return Err(bad(format!(
                "corrupt FMU state: invalid instance state code {code}"
            )));
        }
        Some(s) => s,
    };
    let start_time = r.finite_f64("start time")?;
    let mut opt = |what: &str| -> Result<Option<f64>, ModelError> {
        let defined = r.bool(what)?;
        let v = r.f64(what)?;
        Ok(defined.then_some(v))
    };
    let stop_time = opt("stop time")?;
    let tolerance = opt("tolerance")?;
    let last_successful_time = r.finite_f64("last successful time")?;
    let payload = r.bytes("model state")?;
    r.u64("checksum")?;
    r.finish()?;
    model.deserialize(payload)?;
    let machine = Machine {
        state,
        start_time,
        stop_time,
        tolerance,
        last_successful_time,
    };
    let mut snap = Snapshot::new(machine, model);
    snap.bytes = Some(bytes.to_vec());
    Ok(snap)
}

/// Every field of a serialized FMU state, by offset: the envelope above and the model's own
/// fields (read by restoring `bytes` into a fresh instance of the model the state names, which
/// looks for data files in `resources`). The checksum is the last span. Used by the
/// adversarial harness (`mbcosim state-fields`) to forge states field by field.
pub fn field_map(bytes: &[u8], resources: Option<&Path>) -> Result<Vec<FieldSpan>, ModelError> {
    let mut r = ByteReader::new(bytes);
    r.expect_raw(MAGIC, "magic bytes (not an mbcosim FMU state)")?;
    r.u32("format version")?;
    let ident = r.str("model identifier")?;
    let entry = find_by_identifier(ident)
        .ok_or_else(|| ModelError::BadState(format!("no model `{}`", ident.escape_debug())))?;
    let make = || {
        let mut m = (entry.create)();
        if let Some(dir) = resources {
            let _ = m.set_resource_dir(dir);
        }
        m
    };
    let (res, mut spans) = trace_fields(bytes, || decode(bytes, &make));
    res?;
    spans.sort_by_key(|s| s.offset); // the checksum is read before the model's payload
    Ok(spans)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::pid;

    fn sample() -> Vec<u8> {
        let mut m = pid::create();
        m.set_real(7, 1.0).unwrap();
        m.initialize(0.0).unwrap();
        m.do_step(0.0, 0.1).unwrap();
        let machine = Machine {
            state: State::StepComplete,
            stop_time: Some(5.0),
            last_successful_time: 0.1,
            ..Machine::default()
        };
        Snapshot::new(machine, m).bytes().to_vec()
    }

    #[test]
    fn round_trip_and_every_corruption_is_refused() {
        let bytes = sample();
        let mut snap = decode(&bytes, &pid::create).unwrap();
        assert_eq!(snap.machine.stop_time, Some(5.0));
        assert_eq!(snap.machine.state, State::StepComplete);
        assert_eq!(snap.model.get_real(9).unwrap(), 1.05); // u = kp*e + ki*e*t = 1 + 0.5*0.1
        assert_eq!(snap.bytes(), &bytes[..]);
        for cut in 0..bytes.len() {
            assert!(decode(&bytes[..cut], &pid::create).is_err(), "cut {cut}");
        }
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x01;
            let e = decode(&b, &pid::create)
                .err()
                .unwrap_or_else(|| panic!("flip at {i} accepted"));
            assert!(!e.to_string().is_empty());
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode(&longer, &pid::create).is_err());
        let e = decode(b"garbage!", &pid::create).err().unwrap().to_string();
        assert!(e.contains("magic"), "{e}");
    }

    #[test]
    fn field_map_tiles_the_whole_state() {
        let bytes = sample();
        let spans = field_map(&bytes, None).unwrap();
        let mut at = 0;
        for s in &spans {
            assert_eq!(s.offset, at, "{s:?}");
            at += s.len;
        }
        assert_eq!(at, bytes.len());
        assert_eq!(spans[0].kind, "magic");
        let last = spans.last().unwrap();
        assert_eq!((last.kind, last.what.as_str()), ("u64", "checksum"));
        assert!(spans.iter().any(|s| s.what == "model tag"), "{spans:?}");
    }
}
