//! The points CSV of `eval --points`: the columns `bssrdf sample` writes (`rho`, `theta_deg`,
//! `r` in reduced mean free paths or `r_mm` with --material, `phi_deg`), read whole and
//! checked before anything is printed. Other columns (sample's `pdf`, `phi_prime_deg`, a
//! user's labels) are copied through to the output unchanged, as bytes (spaces and bytes that
//! are not UTF-8 kept); a column named twice, or the output's own `value`, is refused. A UTF-8
//! byte-order mark and quoted fields are accepted; spaces around a header name and around the
//! numbers read are ignored. Errors name the physical line of the row: every line ending
//! (`\n`, `\r\n`, a lone `\r`) counts, blank lines too.

use super::CliError;
use std::io::Write;
use std::path::Path;

/// One point: ρ′, θ and φ in degrees, r in the file's unit (mm with --material).
#[derive(Debug, Clone, Copy)]
pub struct Point {
    pub rho: f64,
    pub theta_deg: f64,
    pub r: f64,
    pub phi_deg: f64,
}

impl Point {
    /// The point with −0 as 0 (IEEE equal; the value given is echoed in the output).
    pub fn unsigned_zeros(self) -> Self {
        Self {
            rho: self.rho + 0.0,
            theta_deg: self.theta_deg + 0.0,
            r: self.r + 0.0,
            phi_deg: self.phi_deg + 0.0,
        }
    }
}

/// The rows of a points file, parsed, with what is needed to write them back.
pub struct Rows {
    /// How errors name the input: its path, or "stdin".
    pub name: String,
    /// The line of each row in the input (1-based), for errors.
    pub lines: Vec<u64>,
    pub points: Vec<Point>,
    headers: csv::ByteRecord,
    records: Vec<csv::ByteRecord>,
    r_column: &'static str,
}

impl Rows {
    /// How the columns of ρ′, θ, r and φ are named in errors.
    pub fn column_names(&self) -> [&'static str; 4] {
        let r = if self.r_column == "r" {
            "column r"
        } else {
            "column r_mm"
        };
        ["column rho", "column theta_deg", r, "column phi_deg"]
    }

    /// Writes the rows back as CSV with a `value` column appended.
    pub fn write_with_values(&self, out: &mut impl Write, values: &[f64]) -> std::io::Result<()> {
        let mut writer = csv::Writer::from_writer(out);
        let mut header = self.headers.clone();
        header.push_field(b"value");
        writer.write_byte_record(&header).map_err(io_error)?;
        for (record, value) in self.records.iter().zip(values) {
            let mut row = record.clone();
            row.push_field(format!("{value:e}").as_bytes());
            writer.write_byte_record(&row).map_err(io_error)?;
        }
        writer.flush()
    }
}

fn io_error(e: csv::Error) -> std::io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(e) => e,
        other => std::io::Error::other(format!("{other:?}")),
    }
}

/// A field without the spaces around it (Unicode white space when the field is UTF-8, ASCII
/// white space otherwise).
fn trimmed(field: &[u8]) -> &[u8] {
    match std::str::from_utf8(field) {
        Ok(text) => text.trim().as_bytes(),
        Err(_) => field.trim_ascii(),
    }
}

/// Physical line numbers of the records of one input. The csv reader's own line is where its
/// read of a record began, before the blank lines it skips, and counts `\n` only; here the
/// line is the one the record's first field is on, counting `\n`, `\r\n` and a lone `\r`.
struct Lines<'a> {
    bytes: &'a [u8],
    /// The bytes before this offset are counted
    counted: usize,
    /// The line the byte at `counted` is on, 1-based
    line: u64,
}

impl<'a> Lines<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            counted: 0,
            line: 1,
        }
    }

    /// The line of the record the reader started reading at `position` (offsets never go
    /// back: records come in order).
    fn of(&mut self, position: Option<&csv::Position>) -> u64 {
        let bytes = self.bytes;
        let start = position
            .and_then(|p| usize::try_from(p.byte()).ok())
            .unwrap_or(self.counted)
            .clamp(self.counted, bytes.len());
        // Skip the blank lines the reader skipped: the record starts at the next other byte
        let first = bytes[start..]
            .iter()
            .position(|b| !matches!(b, b'\r' | b'\n'))
            .map_or(bytes.len(), |i| start + i);
        let head = &bytes[self.counted..first];
        for (i, &b) in head.iter().enumerate() {
            // `first` is never inside a "\r\n": its byte is neither
            if b == b'\n' || (b == b'\r' && head.get(i + 1) != Some(&b'\n')) {
                self.line += 1;
            }
        }
        self.counted = first;
        self.line
    }
}

/// Reads the points of `path` ('-' for stdin). With a material, `material_rho` is its ρ′: a
/// `rho` column may then be present only if every row holds that value.
pub fn read(path: &Path, material_rho: Option<f64>) -> Result<Rows, CliError> {
    let stdin = path == Path::new("-");
    let name = if stdin {
        "stdin".to_string()
    } else {
        path.display().to_string()
    };
    let bytes = if stdin {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)
            .map_err(|e| CliError::input(format!("cannot read the points from stdin: {e}")))?;
        bytes
    } else if path.is_dir() {
        return Err(CliError::input(format!(
            "points file {name} is a folder, not a CSV file"
        )));
    } else {
        std::fs::read(path)
            .map_err(|e| CliError::input(format!("cannot read points file {name}: {e}")))?
    };
    let mut lines_of = Lines::new(&bytes);
    let bad = |e: csv::Error, lines_of: &mut Lines| match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos,
            expected_len,
            len,
        } => CliError::input(format!(
            "{name}:{}: the row has {len} fields, the header {expected_len}",
            lines_of.of(pos.as_ref())
        )),
        _ => CliError::input(format!("points file {name}: {e}")),
    };
    // Not trimmed: the columns copied through stay as they are; the ones read are trimmed here
    let mut reader = csv::ReaderBuilder::new().from_reader(bytes.as_slice());
    let headers = reader
        .byte_headers()
        .map_err(|e| bad(e, &mut lines_of))?
        .clone();
    let names: Vec<&[u8]> = headers.iter().map(trimmed).collect();
    if names.is_empty() || (names.len() == 1 && names[0].is_empty()) {
        return Err(CliError::input(format!(
            "points file {name} is empty: it needs a header naming its columns"
        )));
    }
    let position = |column: &str| names.iter().position(|h| *h == column.as_bytes());
    for (i, h) in names.iter().enumerate() {
        if names.iter().take(i).any(|earlier| earlier == h) {
            return Err(CliError::input(format!(
                "points file {name}: column {:?} appears twice in the header",
                String::from_utf8_lossy(h)
            )));
        }
    }
    if position("value").is_some() {
        return Err(CliError::input(format!(
            "points file {name}: column \"value\" is the one eval writes; rename or drop it"
        )));
    }
    let r_column = match (material_rho, position("r"), position("r_mm")) {
        (Some(_), _, Some(_)) => "r_mm",
        (Some(_), Some(_), None) => {
            return Err(CliError::input(format!(
                "points file {name}: with --material distances are in mm: name the column r_mm, not r"
            )))
        }
        (None, _, Some(_)) => {
            return Err(CliError::input(format!(
                "points file {name}: column r_mm is in mm, which needs --material; without it r is in reduced mean free paths (column r)"
            )))
        }
        (None, _, None) => "r",
        (Some(_), None, None) => "r_mm",
    };
    let missing = |column: &str| {
        let wanted = if material_rho.is_some() {
            "theta_deg,r_mm,phi_deg (and rho only if it equals the material's)"
        } else {
            "rho,theta_deg,r,phi_deg"
        };
        CliError::input(format!(
            "points file {name} has no column {column:?} (the header must name {wanted})"
        ))
    };
    let rho_at = position("rho");
    if material_rho.is_none() && rho_at.is_none() {
        return Err(missing("rho"));
    }
    let theta_at = position("theta_deg").ok_or_else(|| missing("theta_deg"))?;
    let r_at = position(r_column).ok_or_else(|| missing(r_column))?;
    let phi_at = position("phi_deg").ok_or_else(|| missing("phi_deg"))?;

    let (mut points, mut lines, mut records) = (Vec::new(), Vec::new(), Vec::new());
    for record in reader.byte_records() {
        let record = record.map_err(|e| bad(e, &mut lines_of))?;
        let line = lines_of.of(record.position());
        let number = |at: usize, column: &str| -> Result<f64, CliError> {
            let text = String::from_utf8_lossy(trimmed(record.get(at).unwrap_or_default()));
            text.parse().map_err(|_| {
                CliError::input(format!(
                    "{name}:{line}: column {column} = {text:?} is not a number"
                ))
            })
        };
        let rho = match (rho_at, material_rho) {
            (Some(at), Some(m)) => {
                let rho = number(at, "rho")?;
                if (rho - m).abs() > 1e-12 * m.abs().max(1.0) {
                    return Err(CliError::input(format!(
                        "{name}:{line}: column rho = {} conflicts with --material, whose rho' is {} on this channel: drop the column or the flag",
                        super::show(rho),
                        super::show(m)
                    )));
                }
                m
            }
            (Some(at), None) => number(at, "rho")?,
            (None, Some(m)) => m,
            (None, None) => return Err(missing("rho")),
        };
        points.push(
            Point {
                rho,
                theta_deg: number(theta_at, "theta_deg")?,
                r: number(r_at, r_column)?,
                phi_deg: number(phi_at, "phi_deg")?,
            }
            .unsigned_zeros(),
        );
        lines.push(line);
        records.push(record);
    }
    Ok(Rows {
        name,
        lines,
        points,
        headers,
        records,
        r_column,
    })
}
