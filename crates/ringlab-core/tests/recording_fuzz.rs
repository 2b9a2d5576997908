//! Property test of the reader: random and mutated files never make it panic, whatever it
//! accepts is a sound recording, and the motion recovery takes it without a panic. `RINGLAB_FUZZ_CASES` sets the number of inputs (default
//! 40,000: random bytes, random lines, and mutations of the sample's head and of whole files).

mod common;

use ringlab_core::recording::rng::Rng;
use ringlab_core::recording::{is_usable, parse_recording, recover};
use std::path::Path;

const TOKENS: &[&str] = &[
    "",
    " ",
    ",",
    ",,",
    "#",
    "# ",
    "=",
    "# fps = 300",
    "# px_per_mm = -1",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e309",
    "-0",
    "0",
    "1",
    "-1",
    "18446744073709551616",
    "3.5.2",
    "0x10",
    "1_000",
    "+5",
    ".",
    "e5",
    "\u{feff}",
    "\r",
    "\n",
    "\t",
    "# ringlab-recording v1",
    "frame,x1,y1,x2,y2,x3,y3,x4,y4",
    "\u{00e9}",
    "\u{1f600}",
    "9999999999",
    "# shape = disk",
];

fn mutate(rng: &mut Rng, base: &[u8]) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = b.len().max(1);
        match rng.below(9) {
            0 => {
                if !b.is_empty() {
                    let i = rng.below(b.len());
                    b[i] = rng.next_u64() as u8;
                }
            }
            1 => {
                let i = rng.below(len);
                let n = rng.below(8);
                b.drain(i.min(b.len())..(i + n).min(b.len()));
            }
            2 => {
                let i = rng.below(len).min(b.len());
                let t = TOKENS[rng.below(TOKENS.len())];
                b.splice(i..i, t.bytes());
            }
            3 => b.truncate(rng.below(len)),
            _ => {
                // Line-level: swap, duplicate, delete, or replace a field.
                let text = String::from_utf8_lossy(&b).into_owned();
                let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
                if lines.is_empty() {
                    continue;
                }
                let i = rng.below(lines.len());
                let j = rng.below(lines.len());
                match rng.below(4) {
                    0 => lines.swap(i, j),
                    1 => {
                        let l = lines[i].clone();
                        lines.insert(j, l);
                    }
                    2 => {
                        lines.remove(i);
                    }
                    _ => {
                        let mut fields: Vec<String> =
                            lines[i].split(',').map(str::to_string).collect();
                        let k = rng.below(fields.len());
                        fields[k] = TOKENS[rng.below(TOKENS.len())].to_string();
                        lines[i] = fields.join(",");
                    }
                }
                b = lines.join("\n").into_bytes();
            }
        }
    }
    b
}

fn random_lines(rng: &mut Rng) -> Vec<u8> {
    let mut s = String::new();
    if rng.below(2) == 0 {
        s.push_str("# ringlab-recording v1\n");
    }
    for _ in 0..rng.below(20) {
        let fields = rng.below(12);
        let line: Vec<String> = (0..fields)
            .map(|_| match rng.below(3) {
                0 => TOKENS[rng.below(TOKENS.len())].to_string(),
                1 => format!("{}", rng.below(1000)),
                _ => format!("{:.3}", (rng.uniform() - 0.5) * 2000.0),
            })
            .collect();
        s.push_str(&line.join(","));
        s.push('\n');
    }
    s.into_bytes()
}

/// What an accepted file must satisfy; its motion is then recovered (or refused) without a
/// panic either.
fn check_sound(bytes: &[u8]) {
    let Ok(rec) = parse_recording(bytes, Path::new("fuzz.csv")) else { return };
    let _ = recover(&rec);
    let h = &rec.header;
    assert!(h.fps > 0.0 && h.px_per_mm > 0.0 && h.outer_radius_mm > 0.0 && h.width_mm > 0.0);
    assert!(rec.frames.iter().filter(|f| is_usable(f)).count() >= 2);
    for f in &rec.frames {
        for p in f.iter().flatten() {
            assert!(p[0].is_finite() && p[1].is_finite());
        }
    }
}

#[test]
fn random_and_mutated_files_never_panic() {
    let cases: usize =
        std::env::var("RINGLAB_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(40_000);
    let sample = std::fs::read(common::test_data("sample-ring.csv")).expect("sample");
    let text = String::from_utf8_lossy(&sample);
    // The header and 30 frames: mutations then hit the header as often as the frames.
    let head: String = text.lines().take(40).map(|l| format!("{l}\n")).collect();
    let mut rng = Rng::new(0x5eed);
    let mut accepted = 0;
    for i in 0..cases {
        let input = match i % 10 {
            0 => (0..rng.below(200)).map(|_| rng.next_u64() as u8).collect(),
            1 | 2 => random_lines(&mut rng),
            3 if i % 500 == 3 => mutate(&mut rng, &sample),
            _ => mutate(&mut rng, head.as_bytes()),
        };
        check_sound(&input);
        accepted += parse_recording(&input, Path::new("fuzz.csv")).is_ok() as usize;
    }
    eprintln!("{cases} inputs, {accepted} accepted");
    // The mutations must leave some files valid, else they test nothing but the first line.
    assert!(accepted > cases / 50, "only {accepted} of {cases} inputs were valid");
}
