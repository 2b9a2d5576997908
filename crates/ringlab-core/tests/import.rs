//! Lab trackers' files: each format written here from the sample recording (with the quirks of
//! the real tools: low-likelihood guesses, blank cells, calibrated y-up tables with a comma,
//! spots out of order), imported, compared point by point, and fitted back to the truth;
//! malformed files give their file and line.

mod common;

use ringlab_core::analysis::fit::{FitOptions, fit};
use ringlab_core::physics::Shape;
use ringlab_core::recording::import::{
    BodyMm, Format, ImportErrorKind, ImportOptions, Imported, LengthUnit, Source, import,
};
use ringlab_core::recording::{Recording, read_recording};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

const PX_PER_MM: f64 = 3.364764;
const FPS: f64 = 300.0;

fn sample() -> Recording {
    read_recording(&common::test_data("sample-ring.csv")).expect("the sample reads")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ringlab-import-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::write(path, text).expect("writes");
    path.to_path_buf()
}

fn body() -> BodyMm {
    BodyMm { shape: Shape::Ring, outer_radius_mm: 20.66, width_mm: 18.0, thickness_mm: Some(1.0) }
}

fn opts() -> ImportOptions {
    ImportOptions { body: Some(body()), ..ImportOptions::default() }
}

/// The imported marks equal the sample's (up to one shift of the whole image, within the
/// files' rounding), except where `dropped` says a mark was left out on purpose.
fn assert_same_marks(
    got: &Imported,
    want: &Recording,
    dropped: &dyn Fn(usize, usize) -> bool,
    tol_px: f64,
) {
    let g = &got.recording;
    assert_eq!(g.frames.len(), want.frames.len(), "frame count");
    let mut shift: Option<[f64; 2]> = None;
    for (i, (fg, fw)) in g.frames.iter().zip(&want.frames).enumerate() {
        for k in 0..4 {
            match (fg[k], fw[k]) {
                (Some(a), Some(b)) => {
                    assert!(!dropped(i, k), "frame {i} mark {}: should have been dropped", k + 1);
                    let d = [a[0] - b[0], a[1] - b[1]];
                    let s = *shift.get_or_insert(d);
                    assert!(
                        (d[0] - s[0]).abs() < tol_px && (d[1] - s[1]).abs() < tol_px,
                        "frame {i} mark {}: {a:?} against {b:?} (shift {s:?})",
                        k + 1
                    );
                }
                (None, Some(_)) => assert!(dropped(i, k), "frame {i} mark {} lost", k + 1),
                (Some(_), None) => panic!("frame {i} mark {} appeared", k + 1),
                (None, None) => {}
            }
        }
    }
}

/// The fit of an imported recording finds the sample's truth.
fn assert_fits_truth(rec: &Recording, what: &str) {
    let r = fit(rec, &FitOptions::default(), &|_| {}, &AtomicBool::new(false))
        .unwrap_or_else(|e| panic!("{what}: fit: {e}"));
    let truth = [0.031, 0.066, 0.083];
    for i in 0..3 {
        let rel = (r.c[i] - truth[i]).abs() / truth[i];
        assert!(rel < 0.10, "{what}: C{} = {} against {}", i + 1, r.c[i], truth[i]);
    }
    assert!((r.start.theta - 0.56).abs() < 0.02, "{what}: theta0 = {}", r.start.theta);
    assert!(r.rms_px > 0.4 && r.rms_px < 0.6, "{what}: misfit {} px for 0.5 px noise", r.rms_px);
}

/// A DeepLabCut CSV of the sample: an extra bodypart first, the marks out of order, mark 2
/// guessed wrongly at low likelihood every 37th frame, mark 3 blank every 53rd.
fn dlc_file(rec: &Recording, individuals: bool) -> (String, usize, usize) {
    let parts = ["centre", "m3", "m1", "m2", "m4"];
    let mark_of = |p: &str| ["m1", "m2", "m3", "m4"].iter().position(|m| *m == p);
    let mut s = String::from("scorer");
    for _ in 0..parts.len() * 3 {
        s.push_str(",DLC_resnet50_ringMar1shuffle1_100000");
    }
    s.push('\n');
    if individuals {
        s.push_str("individuals");
        for _ in 0..parts.len() * 3 {
            s.push_str(",ring1");
        }
        s.push('\n');
    }
    s.push_str("bodyparts");
    for p in parts {
        write!(s, ",{p},{p},{p}").unwrap();
    }
    s.push_str("\ncoords");
    for _ in parts {
        s.push_str(",x,y,likelihood");
    }
    s.push('\n');
    let (mut low, mut blank) = (0, 0);
    for (i, f) in rec.frames.iter().enumerate() {
        write!(s, "{i}").unwrap();
        let centre =
            f.iter().flatten().fold([0.0, 0.0], |a, p| [a[0] + p[0] / 4.0, a[1] + p[1] / 4.0]);
        for p in parts {
            let Some(k) = mark_of(p) else {
                write!(s, ",{:.3},{:.3},0.99", centre[0], centre[1]).unwrap();
                continue;
            };
            match f[k] {
                Some(q) if k == 1 && i % 37 == 5 => {
                    low += 1;
                    write!(s, ",{:.3},{:.3},0.31", q[0] + 40.0, q[1] - 25.0).unwrap();
                }
                Some(_) if k == 2 && i % 53 == 7 => {
                    blank += 1;
                    s.push_str(",,,");
                }
                Some(q) => write!(s, ",{:.3},{:.3},0.97", q[0], q[1]).unwrap(),
                None => {
                    blank += 1;
                    s.push_str(",,,");
                }
            }
        }
        s.push('\n');
    }
    (s, low, blank)
}

#[test]
fn deeplabcut_csv_is_imported_and_fits_the_truth() {
    let rec = sample();
    let d = dir("dlc");
    let (text, low, blank) = dlc_file(&rec, false);
    let file = write(&d.join("ring.csv"), &text);
    let o = ImportOptions {
        fps: Some(FPS),
        px_per_mm: Some(PX_PER_MM),
        marks: Some(vec!["m1".into(), "m2".into(), "m3".into(), "m4".into()]),
        ..opts()
    };
    let got = import(std::slice::from_ref(&file), None, &o).expect("imports");
    assert_eq!(got.report.source, Source::Dlc, "told from its header");
    assert_eq!(got.report.low_likelihood, low);
    assert!(low > 40, "{low} low-likelihood guesses planted");
    assert_eq!(got.report.blank, blank);
    assert!(
        got.report.notes.iter().any(|n| n.contains(&format!("{low} points below likelihood 0.6"))),
        "{:?}",
        got.report.notes
    );
    assert_eq!(got.recording.header.fps, FPS);
    assert_eq!(got.recording.header.px_per_mm, PX_PER_MM);
    let dropped = |i: usize, k: usize| (k == 1 && i % 37 == 5) || (k == 2 && i % 53 == 7);
    assert_same_marks(&got, &rec, &dropped, 0.006);
    assert_fits_truth(&got.recording, "DeepLabCut");

    // A multi-animal file with one individual names its points by bodypart alone.
    let (text, _, _) = dlc_file(&rec, true);
    let multi = write(&d.join("multi.csv"), &text);
    let got = import(&[multi], Some(Format::Dlc), &o).expect("imports the multi-animal file");
    assert_eq!(got.report.marks, ["m1", "m2", "m3", "m4"]);

    // Marks given out of cyclic order are refused, with the order that works.
    let crossed = ImportOptions {
        marks: Some(vec!["m1".into(), "m3".into(), "m2".into(), "m4".into()]),
        ..o.clone()
    };
    let e = import(std::slice::from_ref(&file), None, &crossed).expect_err("crossed marks");
    assert!(matches!(e.kind, ImportErrorKind::NotCyclic { .. }), "{e}");
    assert!(e.to_string().contains("--marks m1,m2,m3,m4"), "{e}");
    // What the file does not say must be given.
    let e = import(std::slice::from_ref(&file), None, &ImportOptions { fps: None, ..o.clone() })
        .expect_err("no fps");
    assert_eq!(e.kind, ImportErrorKind::MissingFps);
    let e =
        import(std::slice::from_ref(&file), None, &ImportOptions { px_per_mm: None, ..o.clone() })
            .expect_err("no scale");
    assert_eq!(e.kind, ImportErrorKind::MissingScale);
    let e = import(std::slice::from_ref(&file), None, &ImportOptions { body: None, ..o.clone() })
        .expect_err("no body");
    assert_eq!(e.kind, ImportErrorKind::MissingBody);
    let unknown = ImportOptions {
        marks: Some(vec!["m1".into(), "m2".into(), "m3".into(), "tail".into()]),
        ..o
    };
    let e = import(&[file], None, &unknown).expect_err("unknown mark");
    assert!(
        e.to_string().contains("'tail' is not in the file (it has: centre, m3, m1, m2, m4)"),
        "{e}"
    );
}

/// One Tracker data table per mark: calibrated in metres, y up, origin at the image centre,
/// times from 0.5 s; frames where the mark was not found have no row.
fn tracker_tables(rec: &Recording, d: &Path, comma: bool) -> Vec<PathBuf> {
    let sep = if comma { "," } else { "\t" };
    (0..4)
        .map(|k| {
            let mut s = format!("mass {}\nt{sep}x{sep}y{sep}v_x\n", ["A", "B", "C", "D"][k]);
            for (i, f) in rec.frames.iter().enumerate() {
                if let Some(p) = f[k] {
                    let x = (p[0] - 640.0) / PX_PER_MM / 1000.0;
                    let y = -(p[1] - 512.0) / PX_PER_MM / 1000.0;
                    writeln!(s, "{:.6}{sep}{x:.8}{sep}{y:.8}{sep}", (i as f64 + 150.0) / FPS)
                        .unwrap();
                }
            }
            write(&d.join(format!("mass{k}.txt")), &s)
        })
        .collect()
}

#[test]
fn tracker_data_tables_are_imported_and_fit_the_truth() {
    let rec = sample();
    let d = dir("tracker");
    for comma in [false, true] {
        let files = tracker_tables(&rec, &d, comma);
        // The unit is not in a table: it must be said.
        let e = import(&files, Some(Format::Tracker), &opts()).expect_err("no unit");
        assert!(matches!(e.kind, ImportErrorKind::MissingUnit(_)), "{e}");
        let o =
            ImportOptions { unit: LengthUnit::parse("m"), px_per_mm: Some(PX_PER_MM), ..opts() };
        let got = import(&files, None, &o).expect("imports");
        assert_eq!(got.report.source, Source::TrackerTable);
        assert!(
            (got.recording.header.fps - FPS).abs() < 1e-3,
            "frame rate from the times: {}",
            got.recording.header.fps
        );
        assert_eq!(got.report.marks, ["mass A", "mass B", "mass C", "mass D"]);
        assert_same_marks(&got, &rec, &|_, _| false, 0.01);
        if comma {
            assert_fits_truth(&got.recording, "Tracker tables");
        }
    }
}

/// A Tracker project: four point masses and the axes, 300 frames/s, calibrated in metres.
fn trk_file(rec: &Recording) -> String {
    let mut s = String::from(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<object class="org.opensourcephysics.cabrillo.tracker.TrackerPanel">
    <property name="version" type="string">6.1.3</property>
    <property name="videoclip" type="object">
        <object class="org.opensourcephysics.media.core.VideoClip">
            <property name="video" type="object">
                <object class="org.opensourcephysics.media.core.ImageVideo">
                    <property name="path" type="string">ring &amp; table.mp4</property>
                </object>
            </property>
            <property name="startframe" type="int">0</property>
            <property name="stepsize" type="int">1</property>
        </object>
    </property>
    <property name="clipcontrol" type="object">
        <object class="org.opensourcephysics.media.core.ClipControl">
            <property name="delta_t" type="double">3.3333333333333335</property>
        </object>
    </property>
    <property name="coords" type="object">
        <object class="org.opensourcephysics.media.core.ImageCoordSystem">
            <property name="framedata" type="array" class="[Lorg.opensourcephysics.media.core.ImageCoordSystem$FrameData;">
                <property name="[0]" type="object">
                    <object class="org.opensourcephysics.media.core.ImageCoordSystem$FrameData">
                        <property name="xorigin" type="double">640.0</property>
                        <property name="yorigin" type="double">512.0</property>
                        <property name="angle" type="double">0.0</property>
                        <property name="xscale" type="double">3364.764</property>
                        <property name="yscale" type="double">3364.764</property>
                    </object>
                </property>
            </property>
        </object>
    </property>
    <property name="length_unit" type="string">m</property>
    <property name="tracks" type="collection" class="java.util.ArrayList">
        <property name="item" type="object">
            <object class="org.opensourcephysics.cabrillo.tracker.CoordAxes">
                <property name="name" type="string">axes</property>
            </object>
        </property>
"#,
    );
    for k in 0..4 {
        write!(
            s,
            r#"        <property name="item" type="object">
            <object class="org.opensourcephysics.cabrillo.tracker.PointMass">
                <property name="name" type="string">mark {}</property>
                <property name="mass" type="double">1.0</property>
                <property name="framedata" type="array" class="[Lorg.opensourcephysics.cabrillo.tracker.PointMass$FrameData;">
"#,
            k + 1
        )
        .unwrap();
        for (i, f) in rec.frames.iter().enumerate() {
            if let Some(p) = f[k] {
                write!(
                    s,
                    r#"                    <property name="[{i}]" type="object">
                        <object class="org.opensourcephysics.cabrillo.tracker.PointMass$FrameData">
                            <property name="x" type="double">{}</property>
                            <property name="y" type="double">{}</property>
                        </object>
                    </property>
"#,
                    p[0], p[1]
                )
                .unwrap();
            }
        }
        s.push_str("                </property>\n            </object>\n        </property>\n");
    }
    s.push_str("    </property>\n</object>\n");
    s
}

#[test]
fn tracker_project_is_imported_with_its_rate_and_calibration() {
    let rec = sample();
    let d = dir("trk");
    let file = write(&d.join("ring.trk"), &trk_file(&rec));
    let got = import(std::slice::from_ref(&file), None, &opts()).expect("imports");
    assert_eq!(got.report.source, Source::TrackerProject);
    assert!((got.recording.header.fps - FPS).abs() < 1e-9, "fps {}", got.recording.header.fps);
    assert!(
        (got.recording.header.px_per_mm - PX_PER_MM).abs() < 1e-9,
        "scale {}",
        got.recording.header.px_per_mm
    );
    assert!(
        got.report.notes.iter().any(|n| n.contains("axes (CoordAxes)")),
        "{:?}",
        got.report.notes
    );
    assert_same_marks(&got, &rec, &|_, _| false, 1e-9);
    assert_fits_truth(&got.recording, "Tracker project");
}

/// TrackMate's spots: four header rows, the marks' tracks numbered 5, 2, 9, 0, a stray
/// track 3 and spots in no track, every spot in a shuffled order.
fn trackmate_file(rec: &Recording) -> String {
    let ids = [5, 2, 9, 0];
    let mut spots: Vec<String> = Vec::new();
    let mut n = 0;
    for (i, f) in rec.frames.iter().enumerate() {
        for (k, p) in f.iter().enumerate() {
            if let Some(p) = p {
                spots.push(format!(
                    "ID{n},{n},{},50.0,{},{},0.0,{},{i},3.0",
                    ids[k],
                    p[0],
                    p[1],
                    i as f64 / FPS
                ));
                n += 1;
            }
        }
        if i % 100 == 0 {
            spots.push(format!("ID{n},{n},3,10.0,5.0,5.0,0.0,{},{i},3.0", i as f64 / FPS));
            spots.push(format!("ID{n},{n},None,5.0,900.0,100.0,0.0,{},{i},3.0", i as f64 / FPS));
            n += 1;
        }
    }
    // A fixed shuffle (a linear congruential walk over the indices).
    let len = spots.len();
    let mut order: Vec<usize> = (0..len).collect();
    let mut x = 12345u64;
    for i in (1..len).rev() {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        order.swap(i, (x >> 33) as usize % (i + 1));
    }
    let mut s = String::from(
        "LABEL,ID,TRACK_ID,QUALITY,POSITION_X,POSITION_Y,POSITION_Z,POSITION_T,FRAME,RADIUS\n\
         Label,Spot ID,Track ID,Quality,X,Y,Z,T,Frame,Radius\n\
         Label,Spot ID,Track ID,Quality,X,Y,Z,T,Frame,R\n\
         ,,,(quality),(pixel),(pixel),(pixel),(sec),,(pixel)\n",
    );
    for i in order {
        s.push_str(&spots[i]);
        s.push('\n');
    }
    s
}

#[test]
fn trackmate_spots_out_of_order_are_imported_and_fit_the_truth() {
    let rec = sample();
    let d = dir("trackmate");
    let file = write(&d.join("spots.csv"), &trackmate_file(&rec));
    let o = ImportOptions {
        px_per_mm: Some(PX_PER_MM),
        marks: Some(["5", "2", "9", "0"].map(String::from).to_vec()),
        ..opts()
    };
    let got = import(std::slice::from_ref(&file), None, &o).expect("imports");
    assert_eq!(got.report.source, Source::TrackMate);
    assert!(
        (got.recording.header.fps - FPS).abs() < 1e-6,
        "frame rate from POSITION_T: {}",
        got.recording.header.fps
    );
    assert!(
        got.report.notes.iter().any(|n| n.contains("19 spots belong to no track")),
        "{:?}",
        got.report.notes
    );
    assert_same_marks(&got, &rec, &|_, _| false, 1e-9);
    assert_fits_truth(&got.recording, "TrackMate");
    // Without --marks, the first four tracks by id (0, 2, 3, 5) are taken, and that is said.
    let e = import(&[file], None, &ImportOptions { marks: None, ..o }).map(|g| g.report.notes);
    match e {
        Ok(notes) => assert!(
            notes
                .iter()
                .any(|n| n.contains("5 points in the file (0, 2, 3, 5, 9): the first four taken")),
            "{notes:?}"
        ),
        Err(e) => assert!(matches!(e.kind, ImportErrorKind::NotCyclic { .. }), "{e}"),
    }
}

#[test]
fn plain_csv_with_named_columns_in_mm_y_up_is_imported_and_fits_the_truth() {
    let rec = sample();
    let d = dir("plain");
    let mut s = String::from("# exported from a lab's own tracker\nt_s;ax;ay;bx;by;cx;cy;dx;dy\n");
    for (i, f) in rec.frames.iter().enumerate() {
        write!(s, "{:.7}", i as f64 / FPS).unwrap();
        for p in f {
            match p {
                Some(p) => write!(s, ";{:.6};{:.6}", p[0] / PX_PER_MM, -p[1] / PX_PER_MM).unwrap(),
                None => s.push_str(";;"),
            }
        }
        s.push('\n');
    }
    let file = write(&d.join("marks.csv"), &s);
    let e = import(std::slice::from_ref(&file), None, &opts())
        .expect_err("a plain CSV is never guessed");
    assert_eq!(e.kind, ImportErrorKind::UnknownFormat);
    let e = import(std::slice::from_ref(&file), Some(Format::Csv), &opts())
        .expect_err("default columns absent");
    assert_eq!(e.line, Some(2), "{e}");
    assert!(e.to_string().contains("no column 'frame (name them with --columns)'"), "{e}");
    let columns = "time:t_s,ax,ay,bx,by,cx,cy,dx,dy".split(',').map(String::from).collect();
    let o = ImportOptions {
        columns: Some(columns),
        unit: Some(LengthUnit::MM),
        y_up: true,
        px_per_mm: Some(PX_PER_MM),
        ..opts()
    };
    let got = import(&[file], Some(Format::Csv), &o).expect("imports");
    assert!((got.recording.header.fps - FPS).abs() < 1e-3);
    assert_same_marks(&got, &rec, &|_, _| false, 0.01);
    assert_fits_truth(&got.recording, "plain CSV");
}

/// Every format's malformed file names the file and the line.
#[test]
fn malformed_files_give_their_line() {
    let d = dir("malformed");
    let dlc_opts = ImportOptions { fps: Some(FPS), px_per_mm: Some(PX_PER_MM), ..opts() };
    let cases: Vec<(&str, String, Option<Format>, ImportOptions, usize, &str)> = vec![
        (
            "dlc.csv",
            "scorer,s,s,s\nbodyparts,a,a,a\ncoords,x,y,likelihood\n0,1,2,0.9\n1,1,two,0.9\n".into(),
            None,
            dlc_opts.clone(),
            5,
            "a y = 'two' is not a number",
        ),
        ("dlc-coords.csv", "scorer,s,s,s\nbodyparts,a,a,a\ncoords,x,y,p\n0,1,2,0.9\n".into(), None, dlc_opts.clone(), 3, "expected 'x, y, likelihood'"),
        ("dlc-half.csv", "scorer,s,s,s\nbodyparts,a,a,a\ncoords,x,y,likelihood\n0,1,,0.9\n".into(), None, dlc_opts.clone(), 4, "x but not y"),
        (
            "table.txt",
            "mass A\nt\tx\ty\n0.0\t1\t2\n0.1\t1\t2\nlater\t1\t2\n".into(),
            Some(Format::Tracker),
            ImportOptions { unit: Some(LengthUnit::MM), ..dlc_opts.clone() },
            5,
            "t = 'later' is not a number",
        ),
        (
            "project.trk",
            "<?xml version=\"1.0\"?>\n<object class=\"org.opensourcephysics.cabrillo.tracker.TrackerPanel\">\n<property name=\"tracks\" type=\"collection\">\n</object>\n".into(),
            None,
            opts(),
            4,
            "not valid XML",
        ),
        (
            "value.trk",
            "<?xml version=\"1.0\"?>\n<object class=\"org.opensourcephysics.cabrillo.tracker.TrackerPanel\">\n<property name=\"tracks\" type=\"collection\">\n<property name=\"item\" type=\"object\">\n<object class=\"org.opensourcephysics.cabrillo.tracker.PointMass\">\n<property name=\"name\" type=\"string\">a</property>\n<property name=\"framedata\" type=\"array\">\n<property name=\"[0]\" type=\"object\">\n<object class=\"org.opensourcephysics.cabrillo.tracker.PointMass$FrameData\">\n<property name=\"x\" type=\"double\">1.0</property>\n<property name=\"y\" type=\"double\">1.O</property>\n</object></property></property></object></property></property></object>\n".into(),
            None,
            opts(),
            11,
            "y = '1.O' is not a number",
        ),
        (
            "spots.csv",
            "TRACK_ID,FRAME,POSITION_X,POSITION_Y\n0,0,1,2\n0,1,1,2\n0,0,3,4\n".into(),
            None,
            dlc_opts.clone(),
            4,
            "given twice in frame 0 (first on line 2)",
        ),
        ("spots-columns.csv", "TRACK_ID,FRAME,POSITION_X,POS_Y\n0,0,1,2\n".into(), Some(Format::TrackMate), dlc_opts.clone(), 1, "no column 'POSITION_Y'"),
        (
            "plain.csv",
            "frame,x1,y1,x2,y2,x3,y3,x4,y4\n0,1,2,3,4,5,6,7,8\n1.5,1,2,3,4,5,6,7,8\n".into(),
            Some(Format::Csv),
            dlc_opts.clone(),
            3,
            "frame '1.5' is not a whole number",
        ),
    ];
    for (name, text, format, o, line, needle) in cases {
        let file = write(&d.join(name), &text);
        let e = import(std::slice::from_ref(&file), format, &o).expect_err(name);
        let msg = e.to_string();
        assert_eq!(e.line, Some(line), "{name}: {msg}");
        assert!(msg.starts_with(&file.display().to_string()), "{name}: {msg}");
        assert!(msg.contains(needle), "{name}: '{msg}' does not say '{needle}'");
    }
}
