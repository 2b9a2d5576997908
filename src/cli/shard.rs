//! `--shard I/N` (a Slurm job array's task I of N takes every N-th item, I counted from 0) and
//! `--merge` (the shards' CSV tables joined back into one).

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Task `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub fn parse(s: &str) -> Result<Shard> {
        let (i, n) =
            s.split_once('/').with_context(|| format!("--shard '{s}': expected I/N, e.g. 0/8"))?;
        let index: usize =
            i.trim().parse().with_context(|| format!("--shard '{s}': I is not a whole number"))?;
        let count: usize =
            n.trim().parse().with_context(|| format!("--shard '{s}': N is not a whole number"))?;
        if count == 0 || index >= count {
            bail!(
                "--shard '{s}': needs 0 <= I < N (I counts from 0, as in `sbatch --array=0-{}`)",
                count.max(1) - 1
            );
        }
        Ok(Shard { index, count })
    }

    /// Whether item `i` (in the sorted order) belongs to this shard.
    pub fn takes(&self, i: usize) -> bool {
        i % self.count == self.index
    }

    /// The items of this shard, in order.
    pub fn pick<T: Clone>(shard: Option<Shard>, items: &[T]) -> Vec<T> {
        items
            .iter()
            .enumerate()
            .filter(|(i, _)| shard.is_none_or(|s| s.takes(*i)))
            .map(|(_, x)| x.clone())
            .collect()
    }
}

/// One row of a shard table, with where it came from.
pub struct TableRow {
    pub file: PathBuf,
    pub line: usize,
    pub cells: Vec<String>,
}

/// Reads shard tables that must share one header; every row with its file and line.
pub fn read_tables(paths: &[PathBuf]) -> Result<(Vec<String>, Vec<TableRow>)> {
    if paths.is_empty() {
        bail!("--merge: no tables given");
    }
    let mut header: Option<(Vec<String>, &Path)> = None;
    let mut rows = Vec::new();
    for p in paths {
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_path(p)
            .with_context(|| format!("cannot read {}", p.display()))?;
        let mut records = reader.records();
        let first =
            records.next().with_context(|| format!("{}: empty (no header row)", p.display()))?;
        let this: Vec<String> = first
            .with_context(|| format!("{}: line 1", p.display()))?
            .iter()
            .map(str::to_string)
            .collect();
        match &header {
            None => header = Some((this, p)),
            Some((h, from)) if *h != this => {
                bail!(
                    "{}:1: the header differs from {}'s: are these tables of the same command?",
                    p.display(),
                    from.display()
                )
            }
            _ => {}
        }
        for r in records {
            let r = r.with_context(|| format!("{}: not a CSV table", p.display()))?;
            let line = r.position().map_or(0, |q| q.line() as usize);
            rows.push(TableRow {
                file: p.clone(),
                line,
                cells: r.iter().map(str::to_string).collect(),
            });
        }
    }
    Ok((header.map(|h| h.0).unwrap_or_default(), rows))
}

/// Writes a table.
pub fn write_table(path: &Path, header: &[String], rows: &[&TableRow]) -> Result<()> {
    let mut w = csv::Writer::from_path(path)
        .with_context(|| format!("cannot create {}", path.display()))?;
    w.write_record(header)?;
    for r in rows {
        w.write_record(&r.cells)?;
    }
    w.flush().with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cover_every_item_once() {
        let items: Vec<usize> = (0..23).collect();
        for n in [1, 2, 5, 23, 30] {
            let mut all: Vec<usize> = (0..n)
                .flat_map(|i| Shard::pick(Some(Shard { index: i, count: n }), &items))
                .collect();
            all.sort();
            assert_eq!(all, items, "{n} shards");
        }
    }

    #[test]
    fn bad_shards_are_refused() {
        for s in ["3/3", "1", "a/2", "0/0", "-1/2"] {
            assert!(Shard::parse(s).is_err(), "{s}");
        }
        assert_eq!(Shard::parse("2/8").ok(), Some(Shard { index: 2, count: 8 }));
    }
}
