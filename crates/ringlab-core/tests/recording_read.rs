//! The recording reader: the sample read exactly, missing marks, and every problem the
//! format names reported with its line.

mod common;

use ringlab_core::physics::Shape;
use ringlab_core::recording::{
    Camera, ReadErrorKind, parse_recording, read_recording, write_recording, write_recording_exact,
};
use std::path::Path;

fn sample_text() -> String {
    std::fs::read_to_string(common::test_data("sample-ring.csv")).expect("sample readable")
}

/// Parses `text` and returns the error's line and kind.
fn fails(text: &str) -> (Option<usize>, ReadErrorKind) {
    match parse_recording(text.as_bytes(), Path::new("test.csv")) {
        Ok(_) => panic!("accepted:\n{}", text.lines().take(14).collect::<Vec<_>>().join("\n")),
        Err(e) => {
            let shown = e.to_string();
            assert!(shown.starts_with("test.csv"), "error does not name the file: {shown}");
            if let Some(l) = e.line {
                assert!(
                    shown.starts_with(&format!("test.csv:{l}: ")),
                    "error does not show its line: {shown}"
                );
            }
            (e.line, e.kind)
        }
    }
}

/// The sample's header (lines 1-10) and its first `n` frames.
fn head(n: usize) -> String {
    sample_text().lines().take(10 + n).map(|l| format!("{l}\n")).collect()
}

#[test]
fn reads_the_sample_exactly() {
    let text = sample_text();
    let rec = read_recording(&common::test_data("sample-ring.csv")).expect("sample reads");
    let h = &rec.header;
    assert_eq!((h.fps, h.px_per_mm, h.shape), (300.0, 3.364764, Shape::Ring));
    assert_eq!((h.outer_radius_mm, h.width_mm, h.thickness_mm), (20.66, 18.0, Some(1.0)));
    assert_eq!((h.image_width_px, h.image_height_px), (Some(1280.0), Some(1024.0)));
    assert!(h.extra.is_empty());
    assert_eq!(rec.first_frame, 0);
    assert_eq!(rec.frames.len(), 1884);
    // Every number as written in the file.
    for (i, line) in text.lines().skip(10).enumerate() {
        let fields: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
        assert_eq!(fields[0] as usize, i);
        for k in 0..4 {
            assert_eq!(
                rec.frames[i][k],
                Some([fields[1 + 2 * k], fields[2 + 2 * k]]),
                "frame {i} mark {}",
                k + 1
            );
        }
    }
    assert_eq!(rec.time_s(300), 1.0);
}

#[test]
fn missing_marks_are_allowed_and_kept_missing() {
    let mut text = head(6);
    text.push_str("6,,,1.0,2.0,,,3.0,4.0\n7,5,6,,,7,8,,\n8,,,,,,,,\n9,1,2,3,4,5,6,7,8\n");
    let rec = parse_recording(text.as_bytes(), Path::new("t.csv")).expect("reads");
    assert_eq!(rec.frames.len(), 10);
    assert_eq!(rec.frames[6], [None, Some([1.0, 2.0]), None, Some([3.0, 4.0])]);
    assert_eq!(rec.frames[7], [Some([5.0, 6.0]), None, Some([7.0, 8.0]), None]);
    assert_eq!(rec.frames[8], [None; 4]);
    assert_eq!(rec.mark_count(), 6 * 4 + 2 + 2 + 4);
}

#[test]
fn tolerates_crlf_blank_lines_comments_and_unknown_keys() {
    let text = head(3)
        .replace("# fps = 300.0\n", "# fps = 300.0\n# lab = Berkeley\n# a comment\n\n")
        .replace('\n', "\r\n");
    let rec = parse_recording(text.as_bytes(), Path::new("t.csv")).expect("reads");
    assert_eq!(rec.frames.len(), 3);
    assert_eq!(rec.header.extra, vec![("lab".to_string(), "Berkeley".to_string())]);
}

#[test]
fn missing_required_keys_are_named_at_the_end_of_the_header() {
    for key in ["fps", "px_per_mm", "shape", "outer_radius_mm", "width_mm", "thickness_mm"] {
        let text: String = head(5)
            .lines()
            .filter(|l| !l.starts_with(&format!("# {key} =")))
            .map(|l| format!("{l}\n"))
            .collect();
        let (line, kind) = fails(&text);
        assert!(
            matches!(kind, ReadErrorKind::MissingKey { key: k } if k == key),
            "{key}: {kind:?}"
        );
        assert_eq!(line, Some(9), "{key}: the column header line");
    }
    // A disk may leave out its thickness.
    let disk =
        head(5).replace("shape = ring", "shape = disk").replace("# thickness_mm = 1.0\n", "");
    assert!(parse_recording(disk.as_bytes(), Path::new("d.csv")).is_ok());
}

#[test]
fn non_numeric_and_non_finite_values_are_reported_with_their_line() {
    let (line, kind) = fails(&head(5).replace("# fps = 300.0", "# fps = fast"));
    assert_eq!(
        (line, kind),
        (Some(2), ReadErrorKind::NotNumeric { what: "fps".into(), value: "fast".into() })
    );
    let (line, kind) = fails(&head(5).replace("# width_mm = 18.0", "# width_mm = inf"));
    assert_eq!(
        (line, kind),
        (Some(6), ReadErrorKind::NonFinite { what: "width_mm".into(), value: "inf".into() })
    );
    let (line, kind) = fails(&head(5).replace("2,638.76,", "2,abc,"));
    assert_eq!(
        (line, kind),
        (Some(13), ReadErrorKind::NotNumeric { what: "x1".into(), value: "abc".into() })
    );
    let (line, kind) = fails(&head(5).replace(",505.41,", ",NaN,"));
    assert_eq!(
        (line, kind),
        (Some(14), ReadErrorKind::NonFinite { what: "y2".into(), value: "NaN".into() })
    );
    let (line, kind) = fails(&head(5).replace(",585.12,", ",1e400,"));
    assert_eq!(
        (line, kind),
        (Some(14), ReadErrorKind::NonFinite { what: "x4".into(), value: "1e400".into() })
    );
}

#[test]
fn frames_out_of_order_are_reported() {
    let text = sample_text();
    let lines: Vec<&str> = text.lines().take(16).collect();
    let mut swapped = lines.clone();
    swapped.swap(12, 13);
    let (line, kind) = fails(&(swapped.join("\n") + "\n"));
    assert_eq!((line, kind), (Some(13), ReadErrorKind::FrameOutOfOrder { previous: 1, found: 3 }));
    let mut gap = lines.clone();
    gap.remove(13);
    let (line, kind) = fails(&(gap.join("\n") + "\n"));
    assert_eq!((line, kind), (Some(14), ReadErrorKind::FrameOutOfOrder { previous: 2, found: 4 }));
    let mut dup = lines.clone();
    dup.insert(13, lines[12]);
    let (line, kind) = fails(&(dup.join("\n") + "\n"));
    assert_eq!((line, kind), (Some(14), ReadErrorKind::FrameOutOfOrder { previous: 2, found: 2 }));
    let (line, kind) = fails(&head(3).replace("\n2,", "\n-2,"));
    assert_eq!((line, kind), (Some(13), ReadErrorKind::BadFrameNumber { value: "-2".into() }));
}

#[test]
fn fewer_than_two_usable_frames_is_an_error() {
    let (line, kind) = fails(&head(1));
    assert_eq!((line, kind), (Some(11), ReadErrorKind::TooFewUsableFrames { usable: 1 }));
    let (_, kind) = fails(&head(0));
    assert_eq!(kind, ReadErrorKind::TooFewUsableFrames { usable: 0 });
    // Adjacent marks only: point A cannot be found.
    let text = head(0) + "0,1,2,3,4,,,,\n1,1,2,,,,,7,8\n2,1,2,3,4,5,6,,\n";
    let (line, kind) = fails(&text);
    assert_eq!((line, kind), (Some(13), ReadErrorKind::TooFewUsableFrames { usable: 1 }));
}

#[test]
fn scale_and_frame_rate_must_be_positive() {
    for (from, to, key, line) in [
        ("# fps = 300.0", "# fps = 0", "fps", 2),
        ("# px_per_mm = 3.364764", "# px_per_mm = -3.36", "px_per_mm", 3),
        ("# outer_radius_mm = 20.66", "# outer_radius_mm = 0", "outer_radius_mm", 5),
    ] {
        let (l, kind) = fails(&head(5).replace(from, to));
        assert_eq!(l, Some(line));
        assert!(matches!(kind, ReadErrorKind::NotPositive { key: k, .. } if k == key), "{kind:?}");
    }
}

#[test]
fn other_malformed_files_are_reported() {
    assert_eq!(fails("").1, ReadErrorKind::Empty);
    assert_eq!(
        fails("frame,x1\n0,1\n"),
        (Some(1), ReadErrorKind::NotARecording { found: "frame,x1".into() })
    );
    assert_eq!(
        fails(&head(3).replace(" v1", " v2")),
        (Some(1), ReadErrorKind::UnsupportedVersion { found: "v2".into() })
    );
    let (line, kind) = fails(&head(3).replace("frame,x1,y1", "frame,u1,y1"));
    assert_eq!(line, Some(10));
    assert!(matches!(kind, ReadErrorKind::BadColumns { .. }));
    let header_only: String = sample_text().lines().take(9).map(|l| format!("{l}\n")).collect();
    assert_eq!(fails(&header_only), (None, ReadErrorKind::MissingColumns));
    assert_eq!(
        fails(&head(3).replace("\n1,", "\n1,5,")),
        (Some(12), ReadErrorKind::FieldCount { found: 10 })
    );
    assert_eq!(
        fails(&head(3).replace("\n1,657.26,438.40", "\n1,657.26,")),
        (Some(12), ReadErrorKind::HalfMark { mark: 1, present: "x1", missing: "y1" })
    );
    assert_eq!(
        fails(&head(3).replace("# fps = 300.0", "# fps = 300.0\n# fps = 250")),
        (Some(3), ReadErrorKind::DuplicateKey { key: "fps".into(), first_line: 2 })
    );
    assert_eq!(
        fails(&head(3).replace("shape = ring", "shape = torus")),
        (Some(4), ReadErrorKind::UnknownShape { value: "torus".into() })
    );
    let (line, kind) = fails(&head(3).replace("thickness_mm = 1.0", "thickness_mm = 30"));
    assert_eq!(line, Some(7));
    assert!(
        matches!(kind, ReadErrorKind::InvalidBody(ref m) if m.contains("wall thickness")),
        "{kind:?}"
    );
    let mut bytes = head(3).into_bytes();
    let at = bytes.len() - 5;
    bytes[at] = 0xff;
    let e = parse_recording(&bytes, Path::new("b.csv")).unwrap_err();
    assert_eq!((e.line, e.kind), (Some(13), ReadErrorKind::InvalidUtf8));
    let e = read_recording(Path::new("/nonexistent/ringlab/x.csv")).unwrap_err();
    assert!(
        matches!(e.kind, ReadErrorKind::Io(_))
            && e.to_string().contains("/nonexistent/ringlab/x.csv")
    );
}

#[test]
fn camera_keys_are_read_checked_and_written() {
    // The sample with a camera distance on line 10 and a tilt on line 11.
    let with = |d: &str, t: &str| {
        let camera = format!(
            "# image_height_px = 1024\n# camera_distance_mm = {d}\n# camera_tilt_deg = {t}\n"
        );
        head(5).replace("# image_height_px = 1024\n", &camera)
    };
    let rec = parse_recording(with("450", "-12.5").as_bytes(), Path::new("t.csv")).expect("reads");
    let h = &rec.header;
    assert_eq!((h.camera_distance_mm, h.camera_tilt_deg), (Some(450.0), Some(-12.5)));
    assert!(h.extra.is_empty(), "{:?}", h.extra);
    let cam = Camera::for_recording(h, &rec.frames);
    assert_eq!((cam.distance_mm, cam.tilt_rad), (Some(450.0), (-12.5f64).to_radians()));
    let mut out = Vec::new();
    write_recording(&mut out, &rec).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("# camera_distance_mm = 450.0\n# camera_tilt_deg = -12.5\n"), "{text}");
    assert_eq!(parse_recording(text.as_bytes(), Path::new("w.csv")).unwrap().header, rec.header);
    // Absent (the sample): unknown, and the camera is orthographic and untilted; nothing written.
    let rec = parse_recording(head(5).as_bytes(), Path::new("t.csv")).unwrap();
    assert_eq!((rec.header.camera_distance_mm, rec.header.camera_tilt_deg), (None, None));
    let cam = Camera::for_recording(&rec.header, &rec.frames);
    assert_eq!((cam.distance_mm, cam.tilt_rad), (None, 0.0));
    let mut out = Vec::new();
    write_recording(&mut out, &rec).unwrap();
    assert!(!String::from_utf8(out).unwrap().contains("camera_"));
    // A distance must be a positive finite number, a tilt within (-80, 80) degrees.
    let dist = "camera_distance_mm";
    assert_eq!(
        fails(&with("0", "5")),
        (Some(10), ReadErrorKind::NotPositive { key: dist, value: 0.0 })
    );
    assert_eq!(
        fails(&with("-450", "5")),
        (Some(10), ReadErrorKind::NotPositive { key: dist, value: -450.0 })
    );
    assert_eq!(
        fails(&with("inf", "5")),
        (Some(10), ReadErrorKind::NonFinite { what: dist.into(), value: "inf".into() })
    );
    assert_eq!(
        fails(&with("far", "5")),
        (Some(10), ReadErrorKind::NotNumeric { what: dist.into(), value: "far".into() })
    );
    let tilt = "camera_tilt_deg";
    for bad in [80.0, -80.0, 95.0, -400.0] {
        let kind = ReadErrorKind::OutOfRange { key: tilt, value: bad, lo: -80.0, hi: 80.0 };
        assert_eq!(fails(&with("450", &bad.to_string())), (Some(11), kind));
    }
    assert_eq!(
        fails(&with("450", "NaN")),
        (Some(11), ReadErrorKind::NonFinite { what: tilt.into(), value: "NaN".into() })
    );
    let e = parse_recording(with("450", "85").as_bytes(), Path::new("t.csv")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.csv:11: camera_tilt_deg = 85 must lie between -80 and 80 (exclusive)"
    );
    // Just inside the range, and a tilt without a distance, are fine.
    for (d, t) in [("450", "79.9"), ("1e4", "-79.9")] {
        assert!(parse_recording(with(d, t).as_bytes(), Path::new("t.csv")).is_ok(), "{d} {t}");
    }
    let tilt_only = head(5)
        .replace("# image_height_px = 1024\n", "# image_height_px = 1024\n# camera_tilt_deg = 3\n");
    let rec = parse_recording(tilt_only.as_bytes(), Path::new("t.csv")).unwrap();
    assert_eq!((rec.header.camera_distance_mm, rec.header.camera_tilt_deg), (None, Some(3.0)));
}

#[test]
fn an_exact_write_reads_back_every_bit_and_the_plain_one_rounds() {
    let mut rec = parse_recording(head(40).as_bytes(), Path::new("t.csv")).expect("reads");
    // Coordinates with more digits than any decimal rounding keeps, and one mark missing.
    for (i, marks) in rec.frames.iter_mut().enumerate() {
        for m in marks.iter_mut().flatten() {
            m[0] += (i as f64 + 1.0) / 3.0 * 1e-3;
            m[1] -= std::f64::consts::PI * 1e-7;
        }
    }
    rec.frames[3][2] = None;
    let mut exact = Vec::new();
    write_recording_exact(&mut exact, &rec).unwrap();
    let back = parse_recording(exact.as_slice(), Path::new("exact.csv")).expect("reads back");
    assert_eq!(back.header, rec.header);
    assert_eq!(back.frames, rec.frames, "an exact write must read back bit for bit");
    let mut plain = Vec::new();
    write_recording(&mut plain, &rec).unwrap();
    let rounded = parse_recording(plain.as_slice(), Path::new("plain.csv")).expect("reads back");
    assert_ne!(rounded.frames, rec.frames, "the plain write rounds to a hundredth of a pixel");
    assert_eq!(rounded.frames[3][2], None);
    let off = rounded.frames.iter().zip(&rec.frames).flat_map(|(a, b)| a.iter().zip(b));
    for (a, b) in off {
        if let (Some(a), Some(b)) = (a, b) {
            assert!((a[0] - b[0]).abs() <= 0.005 + 1e-9 && (a[1] - b[1]).abs() <= 0.005 + 1e-9);
        }
    }
}
