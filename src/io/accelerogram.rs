//! Ground-motion records: a base acceleration history read from the PEER NGA `.AT2` format or
//! from a two-column CSV of time and acceleration. Time in s from the record's start;
//! acceleration stored in m/s² (a record in g is converted with standard gravity, 9.80665 m/s²).
//!
//! - `.AT2` (PEER NGA): four header lines — a title, the event and station, a line naming the
//!   unit ("ACCELERATION TIME SERIES IN UNITS OF G"), and `NPTS= n, DT= dt SEC` — then the `n`
//!   samples, any number per line, at times 0, dt, 2 dt, …
//! - `.csv`: a header naming the two columns, the second with its unit in parentheses —
//!   `time (s),acceleration (g)`, or `m/s2`, `m/s^2`, `cm/s2`, `gal` — then one `time,value`
//!   row per sample, times strictly increasing.
//!
//! Every sample must be finite and within [`LARGEST`] g; a bad file gets one error naming the
//! file, the line and what is wrong.

use crate::dynamics::ground_motion::synthetic::{SyntheticRecord, synthetic};
pub use crate::dynamics::ground_motion::{Accelerogram, LARGEST, STANDARD_GRAVITY};
use crate::dynamics::ground_motion::{Component, Excitation, GroundMotion, PulseShape, Record};
use crate::geometry::Vector3;
use crate::model::Shaking;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use thiserror::Error;

/// Why a record could not be read.
#[derive(Debug, Error)]
pub enum RecordError {
    /// The file cannot be read (missing, no permission).
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is not a record: where (1-based line, 0 for the file as a whole) and
    /// what is wrong.
    #[error("{}{}: {message}", path.display(), if *line > 0 { format!(":{line}") } else { String::new() })]
    Format {
        /// The file.
        path: PathBuf,
        /// The line, 1-based (0: the file as a whole).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// The 1940 El Centro north–south record (PEER NGA RSN 6, 180°), embedded: a U.S.
/// government record (assets/records/README.md says where from and under which licence).
pub const ELCENTRO: &str = include_str!("../../assets/records/elcentro_1940_ns.AT2");

/// A record by name: `builtin:elcentro` (the embedded [`ELCENTRO`]),
/// `builtin:synthetic?seed=N&pga=G&duration=S` (a generated record,
/// [`crate::dynamics::ground_motion::synthetic`]; every key optional), or a file path.
pub fn load_record(spec: &str) -> Result<Accelerogram, RecordError> {
    match spec.strip_prefix("builtin:") {
        Some("elcentro") => parse_accelerogram(Path::new("builtin:elcentro.AT2"), ELCENTRO),
        Some(query) if query.split('?').next() == Some("synthetic") => {
            let spec = synthetic_spec(query).map_err(|message| RecordError::Format {
                path: PathBuf::from(format!("builtin:{query}")),
                line: 0,
                message,
            })?;
            Ok(synthetic(&spec))
        }
        Some(other) => Err(RecordError::Format {
            path: PathBuf::from(format!("builtin:{other}")),
            line: 0,
            message: "unknown built-in record: expected builtin:elcentro or builtin:synthetic?seed=N&pga=G&duration=S"
                .into(),
        }),
        None => read_accelerogram(Path::new(spec)),
    }
}

/// The engines' ground motion of a scene's `shaking` (read from `scene` — records by paths
/// relative to its folder — amplitudes in the design's g, `g` m/s²), checked: one message
/// naming the component and what is wrong.
pub fn ground_motion(shaking: &Shaking, scene: &Path, g: f64) -> Result<GroundMotion, String> {
    let mut components = Vec::new();
    for (k, c) in shaking.components.iter().enumerate() {
        let at = format!("component {}", k + 1);
        let excitation = match (&c.pulse, &c.harmonic, &c.record) {
            (Some(p), None, None) => {
                let shape = PulseShape::from_name(&p.shape)
                    .ok_or_else(|| format!("{at}: pulse shape '{}': expected rect, sine or ricker", p.shape))?;
                Excitation::Pulse { shape, amplitude: p.amplitude * g, duration: p.duration }
            }
            (None, Some(h), None) => {
                Excitation::Harmonic { amplitude: h.amplitude * g, period: h.period, cycles: h.cycles }
            }
            (None, None, Some(r)) => {
                let spec = if r.starts_with("builtin:") || Path::new(r).is_absolute() {
                    r.clone()
                } else {
                    scene.parent().unwrap_or(Path::new("")).join(r).to_string_lossy().into_owned()
                };
                Excitation::Record(Arc::new(Record::new(load_record(&spec).map_err(|e| format!("{at}: {e}"))?)))
            }
            _ => return Err(format!("{at}: give exactly one of `pulse`, `harmonic`, `record`")),
        };
        let direction = match (c.azimuth, c.direction) {
            (Some(_), Some(_)) => return Err(format!("{at}: give `azimuth` or `direction`, not both")),
            (Some(deg), None) => {
                let (s, c) = deg.to_radians().sin_cos();
                Vector3::new(c, s, 0.0)
            }
            (None, Some(d)) => Vector3::new(d[0], d[1], d[2]),
            (None, None) => Vector3::x(),
        };
        components.push(Component { excitation, direction });
    }
    GroundMotion { components, scale: shaking.scale, supports: shaking.supports.clone() }
        .validated()
        .map_err(|e| e.to_string())
}

/// A ground motion as a caller names it (the command line's options, Python's keywords): at
/// most one of a pulse (`SHAPE:AMP_G,DURATION_S`), a harmonic (`AMP_G,PERIOD_S,CYCLES`) or a
/// record ([`load_record`]'s names) along the horizontal `direction` (degrees), else the scene's
/// own `ground_motion`; times `scale`; moving the named `supports` alone (none: the whole base).
#[derive(Clone, Copy, Debug)]
pub struct NamedMotion<'a> {
    /// A pulse.
    pub pulse: Option<&'a str>,
    /// A harmonic.
    pub sine: Option<&'a str>,
    /// A record.
    pub record: Option<&'a str>,
    /// A factor on the acceleration.
    pub scale: f64,
    /// The horizontal direction, degrees from +x towards +y (the scene's motion names its own).
    pub direction: f64,
    /// The supports it moves alone (empty: the whole base, or the scene's own choice).
    pub supports: &'a [String],
}

/// The motion `named` names for `scene` (read from `path`: the scene's records are relative to
/// it), amplitudes in the design's g, checked, and a label for it. Messages name the option as
/// `prefix` + its name (`--pulse` on the command line, `pulse` in Python).
pub fn named_motion(
    named: &NamedMotion,
    scene: &crate::model::Scene,
    path: &Path,
    prefix: &str,
) -> Result<(GroundMotion, String), String> {
    let g = scene.gravity.norm();
    let (excitation, label) = match (named.pulse, named.sine, named.record) {
        (Some(p), None, None) => {
            (Excitation::parse_pulse(p, g).map_err(|e| format!("{prefix}pulse {e}"))?, format!("pulse {p} (g, s)"))
        }
        (None, Some(s), None) => (
            Excitation::parse_harmonic(s, g).map_err(|e| format!("{prefix}sine {e}"))?,
            format!("harmonic {s} (g, s, cycles)"),
        ),
        (None, None, Some(r)) => {
            let record = load_record(r).map_err(|e| e.to_string())?;
            let label = format!("record {r} ({:.2} s)", record.duration());
            (Excitation::Record(Arc::new(Record::new(record))), label)
        }
        (None, None, None) => {
            let shaking = scene.ground_motion.as_ref().ok_or_else(|| {
                format!(
                    "name a motion: {prefix}pulse, {prefix}sine or {prefix}record, or give the scene a `ground_motion`"
                )
            })?;
            let mut motion =
                ground_motion(shaking, path, g).map_err(|e| format!("{}: ground_motion: {e}", path.display()))?;
            motion.scale *= named.scale;
            if !named.supports.is_empty() {
                motion.supports = named.supports.to_vec();
            }
            return Ok((motion.validated().map_err(|e| e.to_string())?, "the scene's ground motion".into()));
        }
        _ => return Err(format!("give one of {prefix}pulse, {prefix}sine, {prefix}record")),
    };
    let mut motion = GroundMotion::horizontal(excitation, named.direction);
    (motion.scale, motion.supports) = (named.scale, named.supports.to_vec());
    let label = if named.scale != 1.0 { format!("{label}, scaled by {}", named.scale) } else { label };
    Ok((motion.validated().map_err(|e| e.to_string())?, label))
}

/// The synthetic record's parameters from `synthetic?seed=N&pga=G&duration=S` (each bounded).
fn synthetic_spec(query: &str) -> Result<SyntheticRecord, String> {
    let mut spec = SyntheticRecord::default();
    let params = query.split_once('?').map_or("", |q| q.1);
    for kv in params.split('&').filter(|kv| !kv.is_empty()) {
        let (key, value) = kv.split_once('=').unwrap_or((kv, ""));
        let number = value.trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0);
        match (key.trim(), number) {
            ("seed", _) => {
                spec.seed = value.trim().parse().map_err(|_| format!("seed '{value}': expected a whole number"))?
            }
            ("pga", Some(g)) if g <= LARGEST => spec.pga = g,
            ("duration", Some(s)) if (1.0..=600.0).contains(&s) => spec.duration = s,
            ("pga", _) => return Err(format!("pga '{value}': expected a number of g in (0, {LARGEST}]")),
            ("duration", _) => return Err(format!("duration '{value}': expected seconds in [1, 600]")),
            (other, _) => {
                return Err(format!("unknown parameter '{other}': the synthetic record takes seed, pga, duration"));
            }
        }
    }
    Ok(spec)
}

/// Reads a record, its format by its extension (`.at2`, `.csv`, any case).
pub fn read_accelerogram(path: &Path) -> Result<Accelerogram, RecordError> {
    let text = std::fs::read_to_string(path).map_err(|source| RecordError::Read { path: path.into(), source })?;
    parse_accelerogram(path, &text)
}

/// A record from its text, its format by `path`'s extension (`.at2`, `.csv`, any case); errors
/// name `path`.
pub fn parse_accelerogram(path: &Path, text: &str) -> Result<Accelerogram, RecordError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let fail = |line, message: String| RecordError::Format { path: path.into(), line, message };
    match ext.as_deref() {
        Some("at2") => parse_at2(text).map_err(|(line, m)| fail(line, m)),
        Some("csv") => parse_csv(text).map_err(|(line, m)| fail(line, m)),
        _ => Err(fail(0, "unknown record format: expected a .AT2 (PEER NGA) or .csv file".into())),
    }
}

/// A parse failure: the 1-based line and what is wrong.
type Failure = (usize, String);

/// The samples of a PEER NGA `.AT2` text.
fn parse_at2(text: &str) -> Result<Accelerogram, Failure> {
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 4 {
        return Err((lines.len().max(1), "missing header: an .AT2 file starts with four header lines".into()));
    }
    let unit = lines[2].to_ascii_uppercase();
    if !unit.contains("UNITS OF G") {
        return Err((3, format!("unknown unit in {:?}: expected \"UNITS OF G\"", lines[2].trim())));
    }
    let (n, dt) = npts_dt(lines[3])
        .ok_or_else(|| (4, format!("expected \"NPTS= n, DT= dt SEC\", found {:?}", lines[3].trim())))?;
    let mut values = Vec::with_capacity(n);
    for (i, line) in lines.iter().enumerate().skip(4) {
        for word in line.split_whitespace() {
            values.push(sample(word, i + 1, 1.0)?);
        }
    }
    if values.len() != n {
        return Err((lines.len(), format!("NPTS= {n} but {} samples follow", values.len())));
    }
    let times = (0..n).map(|k| k as f64 * dt).collect();
    Ok(Accelerogram { times, acceleration: values.iter().map(|g| g * STANDARD_GRAVITY).collect() })
}

/// `NPTS= n, DT= dt SEC` (the keys in any case, the separators free).
fn npts_dt(line: &str) -> Option<(usize, f64)> {
    let upper = line.to_ascii_uppercase();
    let after = |key: &str| {
        let rest = &upper[upper.find(key)? + key.len()..];
        let rest = rest.trim_start_matches(|c: char| c == '=' || c.is_whitespace());
        let end = rest.find(|c: char| c == ',' || c.is_whitespace()).unwrap_or(rest.len());
        Some(rest[..end].to_string())
    };
    let n: usize = after("NPTS")?.parse().ok()?;
    let dt: f64 = after("DT")?.parse().ok()?;
    (n > 0 && dt.is_finite() && dt > 0.0).then_some((n, dt))
}

/// One sample on 1-based line `line` in its record's unit (`in_g` g): finite and within
/// [`LARGEST`] g.
fn sample(word: &str, line: usize, in_g: f64) -> Result<f64, Failure> {
    let v: f64 = word.parse().map_err(|_| (line, format!("{word:?} is not a number")))?;
    if !v.is_finite() {
        return Err((line, format!("{word:?} is not a finite acceleration")));
    }
    if (v * in_g).abs() > LARGEST {
        let g = v * in_g;
        return Err((line, format!("{g} g is beyond {LARGEST} g: a wrong unit or a corrupt record")));
    }
    Ok(v)
}

/// The samples of a two-column CSV text (module docs).
fn parse_csv(text: &str) -> Result<Accelerogram, Failure> {
    let mut rows = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = rows.next().ok_or((1, "empty record".to_string()))?;
    let to_si = csv_unit(header)?;
    let (mut times, mut acceleration) = (Vec::new(), Vec::new());
    for (i, row) in rows {
        let line = i + 1;
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        let [t, a] = cells[..] else {
            return Err((line, format!("expected two columns (time, acceleration), found {}", cells.len())));
        };
        let t: f64 = t.parse().map_err(|_| (line, format!("time {t:?} is not a number")))?;
        if !t.is_finite() {
            return Err((line, format!("time {t} is not finite")));
        }
        if let Some(&last) = times.last()
            && t <= last
        {
            let what = if t == last { "repeats" } else { "goes back from" };
            return Err((line, format!("time {t} s {what} the previous row's {last} s: times must increase")));
        }
        let a = sample(a, line, to_si / STANDARD_GRAVITY)?;
        times.push(t);
        acceleration.push(a * to_si);
    }
    if times.is_empty() {
        return Err((2, "no samples after the header".into()));
    }
    Ok(Accelerogram { times, acceleration })
}

/// The factor to m/s² of the acceleration column named in CSV `header`'s second cell.
fn csv_unit(header: &str) -> Result<f64, Failure> {
    let cells: Vec<&str> = header.split(',').map(str::trim).collect();
    if cells.len() != 2 || cells.iter().any(|c| c.parse::<f64>().is_ok()) {
        return Err((
            1,
            format!("missing header: expected e.g. \"time (s),acceleration (g)\", found {:?}", header.trim()),
        ));
    }
    let unit = cells[1]
        .split_once('(')
        .and_then(|(_, u)| u.strip_suffix(')'))
        .map(|u| u.trim().to_ascii_lowercase().replace(' ', ""));
    match unit.as_deref() {
        Some("g") => Ok(STANDARD_GRAVITY),
        Some("m/s2" | "m/s^2" | "m/s/s") => Ok(1.0),
        Some("cm/s2" | "cm/s^2" | "cm/s/s" | "gal") => Ok(0.01),
        Some(u) => Err((1, format!("unknown unit {u:?}: expected g, m/s2 or cm/s2 (gal)"))),
        None => Err((1, format!("the acceleration column {:?} names no unit: e.g. \"acceleration (g)\"", cells[1]))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file in the system's temporary folder with `text`, named for the test.
    fn write(name: &str, text: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!("voussoir-record-{}-{name}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    fn error(name: &str, text: &str) -> String {
        let path = write(name, text);
        let e = read_accelerogram(&path).unwrap_err().to_string();
        std::fs::remove_file(&path).ok();
        assert!(e.starts_with(&path.display().to_string()), "the error names the file: {e}");
        e
    }

    const AT2: &str = "PEER NGA STRONG MOTION DATABASE RECORD\nImperial Valley, test station\n\
        ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    7, DT=   .0100 SEC\n\
        0.0 0.1 -0.2 0.3 0.4\n-0.5 .6\n";

    /// Invariant: an .AT2 file's samples sit at k dt and convert from g by standard gravity.
    #[test]
    fn an_at2_record_is_read_at_its_step_in_metres_per_second_squared() {
        let path = write("ok.AT2", AT2);
        let r = read_accelerogram(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(r.times.len(), 7);
        assert!((r.times[6] - 0.06).abs() < 1e-15 && (r.duration() - 0.06).abs() < 1e-15);
        assert!((r.acceleration[2] + 0.2 * STANDARD_GRAVITY).abs() < 1e-12);
        assert!((r.peak() - 0.6 * STANDARD_GRAVITY).abs() < 1e-12);
    }

    /// Invariant: a CSV's unit converts as named (1 gal = 0.01 m/s²), its times kept as given.
    #[test]
    fn a_csv_record_converts_its_named_unit() {
        let path = write("ok.csv", "time (s), acceleration (gal)\n0.0, 0.0\n0.02, 150.0\n0.05, -300\n");
        let r = read_accelerogram(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(r.times, vec![0.0, 0.02, 0.05]);
        assert_eq!(r.acceleration, vec![0.0, 1.5, -3.0]);
    }

    /// Invariant: every bad record gets one error naming the file and, where it has one, the
    /// line and what is wrong.
    #[test]
    fn bad_records_name_the_file_the_line_and_the_fault() {
        let at2 = |n: &str, t: &str| error(&format!("{n}.at2"), t);
        let csv = |n: &str, t: &str| error(&format!("{n}.csv"), t);
        assert!(at2("nan", &AT2.replace("0.3", "NaN")).contains(":5: \"NaN\" is not a finite"));
        assert!(at2("count", &AT2.replace("NPTS=    7", "NPTS=    8")).contains("NPTS= 8 but 7 samples"));
        assert!(at2("unit", &AT2.replace("UNITS OF G", "UNITS OF CM/S/S")).contains(":3: unknown unit"));
        assert!(at2("short", "PEER\nonly two lines\n").contains("missing header"));
        assert!(at2("dt", &AT2.replace(".0100", "-1")).contains(":4: expected \"NPTS= n, DT= dt SEC\""));
        assert!(at2("large", &AT2.replace("0.4", "45")).contains(":5: 45 g is beyond 20 g"));
        assert!(csv("header", "0.0,0.1\n0.1,0.2\n").contains(":1: missing header"));
        assert!(csv("unknown", "time (s),acc (furlongs)\n0,0\n").contains(":1: unknown unit \"furlongs\""));
        assert!(csv("nounit", "time,acc\n0,0\n").contains(":1: the acceleration column \"acc\" names no unit"));
        assert!(csv("unsorted", "time (s),acc (g)\n0,0\n0.2,0.1\n0.1,0.1\n").contains(":4: time 0.1 s goes back"));
        assert!(csv("repeated", "time (s),acc (g)\n0,0\n0,0.1\n").contains(":3: time 0 s repeats"));
        assert!(csv("columns", "time (s),acc (g)\n0,0,1\n").contains(":2: expected two columns"));
        assert!(csv("empty", "time (s),acc (g)\n").contains("no samples"));
        assert!(csv("inf", "time (s),acc (g)\n0,inf\n").contains(":2: \"inf\" is not a finite"));
        assert!(error("x.txt", "1,2\n").contains("unknown record format"));
        let missing = read_accelerogram(Path::new("/nonexistent/record.at2")).unwrap_err().to_string();
        assert!(missing.starts_with("/nonexistent/record.at2: cannot read"), "{missing}");
    }
}
