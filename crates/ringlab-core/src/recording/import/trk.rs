//! Open Source Physics Tracker's project file (`.trk`, OSP XML): each `PointMass`'s raw pixel
//! positions per video frame (`framedata`, `[n]` the frame), the frame duration `delta_t` (ms)
//! and the calibration (`coords`: pixels per unit; `length_unit`).

use super::points::PointTracks;
use super::unit::LengthUnit;
use super::{ImportError, ImportErrorKind};
use quick_xml::events::Event;
use std::path::Path;

const FORMAT: &str = "Tracker project";

/// One XML element, with what the OSP format keeps in it.
#[derive(Debug, Default)]
struct Node {
    tag: String,
    /// The `name` attribute (a `property`'s name).
    name: String,
    /// The `class` attribute (an `object`'s Java class).
    class: String,
    text: String,
    line: usize,
    children: Vec<Node>,
}

impl Node {
    fn prop(&self, name: &str) -> Option<&Node> {
        self.children.iter().find(|c| c.tag == "property" && c.name == name)
    }
    fn object(&self) -> Option<&Node> {
        self.children.iter().find(|c| c.tag == "object")
    }
    /// `property name` → its `object`.
    fn object_at(&self, name: &str) -> Option<&Node> {
        self.prop(name).and_then(Node::object)
    }
    fn number(&self, name: &str) -> Result<Option<f64>, (usize, ImportErrorKind)> {
        let Some(p) = self.prop(name) else { return Ok(None) };
        let v = p.text.trim();
        match v.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(Some(x)),
            Ok(_) => {
                Err((p.line, ImportErrorKind::NonFinite { what: name.into(), value: v.into() }))
            }
            Err(_) => Err((
                p.line,
                ImportErrorKind::NotNumeric { what: name.into(), value: super::table::clip(v) },
            )),
        }
    }
}

pub fn read(path: &Path, bytes: &[u8]) -> Result<PointTracks, ImportError> {
    let err = |line: Option<usize>, kind| ImportError::new(path, line, kind);
    let at = |(line, kind): (usize, ImportErrorKind)| err(Some(line), kind);
    let root = parse(path, bytes)?;
    if root.tag != "object" || !root.class.ends_with("TrackerPanel") {
        let what = format!(
            "the root element is <{} class=\"{}\">, expected a TrackerPanel object",
            root.tag, root.class
        );
        return Err(err(Some(root.line), ImportErrorKind::NotThisFormat { format: FORMAT, what }));
    }
    let mut out = PointTracks::new(Some(LengthUnit::Px), Some(LengthUnit::Px), false);

    // Time: ms per video frame, on the video or the clip control; steps of `stepsize` frames.
    let clip = root.object_at("videoclip");
    let delta_t = match clip
        .and_then(|c| c.object_at("video"))
        .map(|v| v.number("delta_t"))
        .transpose()
        .map_err(at)?
        .flatten()
    {
        Some(d) => Some(d),
        None => root
            .object_at("clipcontrol")
            .map(|c| c.number("delta_t"))
            .transpose()
            .map_err(at)?
            .flatten(),
    };
    let start =
        clip.map(|c| c.number("startframe")).transpose().map_err(at)?.flatten().unwrap_or(0.0)
            as i64;
    let step = clip
        .map(|c| c.number("stepsize"))
        .transpose()
        .map_err(at)?
        .flatten()
        .unwrap_or(1.0)
        .max(1.0) as i64;
    out.fps = delta_t.filter(|d| *d > 0.0).map(|d| 1000.0 / (d * step as f64));

    // Calibration: pixels per length unit in frame 0's coordinate system.
    let unit = root.prop("length_unit").map(|p| p.text.trim().to_string());
    let coords = root.object_at("coords").and_then(|c| c.prop("framedata"));
    let first = coords.and_then(|f| f.children.iter().find_map(Node::object));
    if let Some(f) = first {
        let (sx, sy) = (f.number("xscale").map_err(at)?, f.number("yscale").map_err(at)?);
        let scale = match (sx, sy) {
            (Some(x), Some(y)) if (x - y).abs() > 1e-9 * x.abs() => {
                out.notes.push(format!("the calibration's x and y scales differ ({x} and {y}): their geometric mean taken"));
                Some((x * y).sqrt())
            }
            (Some(x), _) | (None, Some(x)) => Some(x),
            _ => None,
        };
        match (scale, unit.as_deref().map(|u| (u, LengthUnit::parse(u)))) {
            (Some(s), Some((_, Some(LengthUnit::Length { mm, .. })))) if s > 0.0 => {
                out.px_per_mm = Some(s / mm)
            }
            (Some(_), Some((u, None))) => out
                .notes
                .push(format!("length unit '{u}' is not one of mm, cm, m: give --px-per-mm")),
            _ => out
                .notes
                .push("the project's calibration has no length unit: give --px-per-mm".into()),
        }
        if coords.is_some_and(|c| c.children.iter().filter_map(Node::object).count() > 1) {
            out.notes
                .push("the calibration changes during the video: frame 0's scale taken".into());
        }
    }

    let tracks = root
        .prop("tracks")
        .map(|t| t.children.iter().filter(|c| c.tag == "property").collect::<Vec<_>>())
        .unwrap_or_default();
    let mut others = Vec::new();
    for item in tracks {
        let Some(obj) = item.object() else { continue };
        let name = obj.prop("name").map(|p| p.text.trim().to_string()).unwrap_or_default();
        if !obj.class.ends_with(".PointMass") {
            others.push(format!("{name} ({})", obj.class.rsplit('.').next().unwrap_or("")));
            continue;
        }
        if out.tracks.iter().any(|t| t.name == name) {
            let msg = format!("two point masses are named '{name}'");
            return Err(err(Some(obj.line), ImportErrorKind::BadOption(msg)));
        }
        out.track_mut(&name);
        let Some(data) = obj.prop("framedata") else { continue };
        for slot in data.children.iter().filter(|c| c.tag == "property") {
            let n = slot
                .name
                .strip_prefix('[')
                .and_then(|s| s.strip_suffix(']'))
                .and_then(|s| s.parse::<i64>().ok());
            let Some(n) = n else {
                let what = format!("frame data named '{}', expected [n]", slot.name);
                return Err(err(
                    Some(slot.line),
                    ImportErrorKind::NotThisFormat { format: FORMAT, what },
                ));
            };
            let Some(p) = slot.object() else { continue };
            if (n - start) % step != 0 {
                let what = format!(
                    "frame {n} is not a step of the clip (start {start}, step size {step})"
                );
                return Err(err(
                    Some(slot.line),
                    ImportErrorKind::NotThisFormat { format: FORMAT, what },
                ));
            }
            match (p.number("x").map_err(at)?, p.number("y").map_err(at)?) {
                (Some(x), Some(y)) => {
                    let track = out.tracks.last_mut().expect("pushed above");
                    track.points.insert((n - start) / step, [x, y]);
                }
                (None, None) => out.blank += 1,
                _ => {
                    return Err(err(
                        Some(p.line),
                        ImportErrorKind::HalfPoint { what: name.clone() },
                    ));
                }
            }
        }
    }
    if !others.is_empty() {
        out.notes.push(format!("tracks that are not point masses left out: {}", others.join(", ")));
    }
    Ok(out)
}

/// The XML as a tree of [`Node`]s, each with its line.
fn parse(path: &Path, bytes: &[u8]) -> Result<Node, ImportError> {
    let err = |line, kind| ImportError::new(path, line, kind);
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        err(Some(line), ImportErrorKind::Xml("not valid UTF-8".into()))
    })?;
    let line_at = |pos: u64| {
        1 + text.as_bytes()[..(pos as usize).min(text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut stack: Vec<Node> = vec![Node::default()];
    let xml_err =
        |e: quick_xml::Error, pos| err(Some(line_at(pos)), ImportErrorKind::Xml(e.to_string()));
    loop {
        let pos = reader.buffer_position();
        let event = reader.read_event().map_err(|e| xml_err(e, reader.error_position()))?;
        match event {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let mut node = Node {
                    tag: e.name().as_ref().to_string(),
                    line: line_at(pos),
                    ..Node::default()
                };
                for a in e.attributes() {
                    let a = a.map_err(|e| xml_err(e.into(), pos))?;
                    let v = a
                        .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                        .map_err(|e| xml_err(e, pos))?
                        .into_owned();
                    match a.key.as_ref() {
                        "name" => node.name = v,
                        "class" => node.class = v,
                        _ => {}
                    }
                }
                if matches!(event, Event::Start(_)) {
                    stack.push(node);
                } else if let Some(top) = stack.last_mut() {
                    top.children.push(node);
                }
            }
            Event::End(_) => {
                let node = stack.pop().filter(|_| !stack.is_empty());
                match (node, stack.last_mut()) {
                    (Some(node), Some(top)) => top.children.push(node),
                    _ => {
                        return Err(err(
                            Some(line_at(pos)),
                            ImportErrorKind::Xml("a closing tag without its opening tag".into()),
                        ));
                    }
                }
            }
            Event::Text(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(&t.xml10_content());
                }
            }
            Event::CData(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(&t.xml10_content());
                }
            }
            Event::GeneralRef(r) => {
                let resolved = match r.resolve_char_ref() {
                    Ok(Some(c)) => c.to_string(),
                    _ => quick_xml::escape::resolve_predefined_entity(&r).unwrap_or("").to_string(),
                };
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(&resolved);
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if stack.len() != 1 {
        return Err(err(
            Some(line_at(text.len() as u64)),
            ImportErrorKind::Xml("the file ends inside an element".into()),
        ));
    }
    let doc = stack.pop().unwrap_or_default();
    doc.children
        .into_iter()
        .next()
        .ok_or_else(|| err(None, ImportErrorKind::Xml("no root element".into())))
}
