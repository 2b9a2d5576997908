//! Rows of a delimited text file with their line numbers (the `csv` crate does the quoting),
//! and the cell readers every importer shares.

use super::{ImportError, ImportErrorKind};
use std::path::Path;

/// One row: its 1-based line and its cells, trimmed.
#[derive(Clone, Debug)]
pub struct Row {
    pub line: usize,
    pub cells: Vec<String>,
}

impl Row {
    /// The cell at `i`, empty when the row is short.
    pub fn cell(&self, i: usize) -> &str {
        self.cells.get(i).map_or("", String::as_str)
    }
}

/// The delimiter a header line uses: tab, then semicolon (when no comma), else comma.
pub fn delimiter_of(line: &str) -> u8 {
    if line.contains('\t') {
        b'\t'
    } else if line.contains(';') && !line.contains(',') {
        b';'
    } else {
        b','
    }
}

/// Every row of the file (blank lines left out), a byte-order mark removed.
pub fn rows(path: &Path, bytes: &[u8], delimiter: u8) -> Result<Vec<Row>, ImportError> {
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .delimiter(delimiter)
        .trim(csv::Trim::All)
        .from_reader(bytes);
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map(|p| p.line() as usize);
            let msg = match e.kind() {
                csv::ErrorKind::Utf8 { .. } => "the line is not valid UTF-8".to_string(),
                _ => e.to_string(),
            };
            ImportError::new(path, line, ImportErrorKind::Csv(msg))
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.iter().all(str::is_empty) {
            continue;
        }
        out.push(Row { line, cells: record.iter().map(str::to_string).collect() });
    }
    Ok(out)
}

/// A number cell: `None` when blank or NaN (trackers write both for "nothing found").
pub fn number(what: &str, cell: &str) -> Result<Option<f64>, ImportErrorKind> {
    if cell.is_empty() || cell.eq_ignore_ascii_case("nan") {
        return Ok(None);
    }
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v)),
        Ok(_) => Err(ImportErrorKind::NonFinite { what: what.to_string(), value: clip(cell) }),
        Err(_) => Err(ImportErrorKind::NotNumeric { what: what.to_string(), value: clip(cell) }),
    }
}

/// A point from its x and y cells: both or neither.
pub fn point(what: &str, x: &str, y: &str) -> Result<Option<[f64; 2]>, ImportErrorKind> {
    match (number(&format!("{what} x"), x)?, number(&format!("{what} y"), y)?) {
        (Some(x), Some(y)) => Ok(Some([x, y])),
        (None, None) => Ok(None),
        _ => Err(ImportErrorKind::HalfPoint { what: what.to_string() }),
    }
}

/// A frame number: a whole number (written `12` or `12.0`).
pub fn frame(cell: &str) -> Result<i64, ImportErrorKind> {
    let bad = || ImportErrorKind::BadFrame { value: clip(cell) };
    if let Ok(n) = cell.parse::<i64>() {
        return Ok(n);
    }
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() && v.fract() == 0.0 && v.abs() < 1e12 => Ok(v as i64),
        _ => Err(bad()),
    }
}

/// A value quoted in an error, cut to a readable length.
pub fn clip(s: &str) -> String {
    const MAX: usize = 60;
    match s.char_indices().nth(MAX) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s.to_string(),
    }
}

/// Where the named column is (exact name first, then ignoring case).
pub fn column(header: &Row, name: &str) -> Option<usize> {
    header
        .cells
        .iter()
        .position(|c| c == name)
        .or_else(|| header.cells.iter().position(|c| c.eq_ignore_ascii_case(name)))
}

/// The header's columns, for an error.
pub fn listed(header: &Row) -> String {
    clip(&header.cells.join(", "))
}
