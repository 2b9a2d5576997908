//! The small dialog that asks what a tracker's file does not say (frame rate, scale, the body,
//! which points are the marks) when File > Open or a drop meets one; what was given is
//! remembered (in the settings) for the next file.

use super::controls::preset_picker_ui;
use crate::config::load_preset;
use crate::physics::Shape;
use crate::recording::import::{BodyMm, DEFAULT_MIN_LIKELIHOOD, Format, ImportOptions, LengthUnit};
use crate::session::PendingImport;
use eframe::egui;
use serde::{Deserialize, Serialize};

/// The dialog's fields as typed (kept as text so that a half-typed number is not lost).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct ImportForm {
    /// `auto`, or a `--from` name.
    pub format: String,
    pub fps: String,
    pub px_per_mm: String,
    /// A preset's body, or empty for the fields below.
    pub preset: String,
    pub shape: String,
    pub outer_radius_mm: String,
    pub width_mm: String,
    pub thickness_mm: String,
    pub marks: String,
    /// Empty: as the file says.
    pub unit: String,
    pub columns: String,
    pub y_up: bool,
    pub min_likelihood: String,
}

impl Default for ImportForm {
    fn default() -> Self {
        ImportForm {
            format: "auto".into(),
            fps: String::new(),
            px_per_mm: String::new(),
            // No body is assumed: the dialog asks for one.
            preset: String::new(),
            shape: "ring".into(),
            outer_radius_mm: String::new(),
            width_mm: String::new(),
            thickness_mm: String::new(),
            marks: String::new(),
            unit: String::new(),
            columns: String::new(),
            y_up: false,
            min_likelihood: DEFAULT_MIN_LIKELIHOOD.to_string(),
        }
    }
}

fn number(label: &str, text: &str) -> Result<Option<f64>, String> {
    let t = text.trim();
    if t.is_empty() {
        return Ok(None);
    }
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(v)),
        _ => Err(format!("{label}: '{t}' is not a positive number")),
    }
}

fn list(text: &str) -> Option<Vec<String>> {
    let t = text.trim();
    (!t.is_empty()).then(|| t.split(',').map(|p| p.trim().to_string()).collect())
}

impl ImportForm {
    /// The options the fields give (an error names the field).
    pub fn to_options(&self) -> Result<(Option<Format>, ImportOptions), String> {
        let format = match self.format.as_str() {
            "auto" | "" => None,
            f => Some(
                Format::parse(f)
                    .ok_or_else(|| format!("format '{f}' is not one of auto, {}", Format::NAMES))?,
            ),
        };
        let body = if self.preset.is_empty() {
            let shape = Shape::parse(&self.shape)
                .ok_or_else(|| format!("shape '{}' is neither ring nor disk", self.shape))?;
            match (number("outer radius", &self.outer_radius_mm)?, number("width", &self.width_mm)?)
            {
                (Some(r), Some(h)) => Some(BodyMm {
                    shape,
                    outer_radius_mm: r,
                    width_mm: h,
                    thickness_mm: number("wall", &self.thickness_mm)?,
                }),
                _ => None,
            }
        } else {
            let case = load_preset(&self.preset).map_err(|e| e.to_string())?;
            Some(BodyMm::of_case(&case)?)
        };
        let unit = match self.unit.trim() {
            "" => None,
            u => Some(
                LengthUnit::parse(u)
                    .ok_or_else(|| format!("unit '{u}' is not one of {}", LengthUnit::NAMES))?,
            ),
        };
        let min_likelihood = match self.min_likelihood.trim().parse::<f64>() {
            Ok(v) if (0.0..=1.0).contains(&v) => v,
            _ => {
                return Err(format!(
                    "minimum likelihood '{}' is not a number from 0 to 1",
                    self.min_likelihood.trim()
                ));
            }
        };
        let opts = ImportOptions {
            fps: number("frames per second", &self.fps)?,
            px_per_mm: number("pixels per mm", &self.px_per_mm)?,
            marks: list(&self.marks),
            min_likelihood,
            body,
            columns: list(&self.columns),
            unit,
            y_up: self.y_up,
        };
        Ok((format, opts))
    }
}

/// What the dialog's buttons asked for.
#[derive(Clone, Debug, PartialEq)]
pub enum ImportDialogAction {
    Open(Option<Format>, ImportOptions),
    Cancel,
}

/// The dialog over the window; `problem` keeps the last form error until the next try.
pub fn import_dialog_ui(
    ctx: &egui::Context,
    pending: &PendingImport,
    form: &mut ImportForm,
    problem: &mut Option<String>,
) -> Option<ImportDialogAction> {
    let mut action = None;
    let name = pending
        .path
        .file_name()
        .map_or(pending.path.display().to_string(), |n| n.to_string_lossy().into_owned());
    egui::Window::new("Open a tracker's file")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            ui.label(egui::RichText::new(&name).strong());
            ui.label(
                egui::RichText::new(pending.error.kind.to_string())
                    .color(ui.visuals().warn_fg_color),
            );
            ui.add_space(4.0);
            egui::Grid::new("import-form").num_columns(2).spacing([8.0, 4.0]).show(ui, |ui| {
                ui.label("Format");
                egui::ComboBox::from_id_salt("import-format")
                    .selected_text(form.format.clone())
                    .show_ui(ui, |ui| {
                        for f in ["auto", "dlc", "tracker", "trackmate", "csv"] {
                            ui.selectable_value(&mut form.format, f.to_string(), f);
                        }
                    });
                ui.end_row();
                field_ui(ui, "Frames per second", &mut form.fps, "as the file says");
                field_ui(ui, "Pixels per mm", &mut form.px_per_mm, "as the file says");
                ui.label("Body");
                ui.horizontal(|ui| {
                    let current =
                        if form.preset.is_empty() { "custom" } else { form.preset.as_str() };
                    if let Some(p) = preset_picker_ui(ui, "", current) {
                        form.preset = p;
                    }
                    if ui.selectable_label(form.preset.is_empty(), "custom").clicked() {
                        form.preset.clear();
                    }
                });
                ui.end_row();
                if form.preset.is_empty() {
                    ui.label("Shape");
                    ui.horizontal(|ui| {
                        ui.selectable_value(&mut form.shape, "ring".to_string(), "ring");
                        ui.selectable_value(&mut form.shape, "disk".to_string(), "disk");
                    });
                    ui.end_row();
                    field_ui(ui, "Outer radius (mm)", &mut form.outer_radius_mm, "");
                    field_ui(ui, "Width (mm)", &mut form.width_mm, "");
                    field_ui(ui, "Wall (mm)", &mut form.thickness_mm, "a ring's");
                }
                field_ui(ui, "Marks", &mut form.marks, "A,B,C,D in order round the rim");
                field_ui(ui, "Unit", &mut form.unit, "as the file says (px, um, mm, cm, m)");
                field_ui(ui, "Columns (plain CSV)", &mut form.columns, "frame,x1,y1,..,x4,y4");
                ui.label("y grows upward");
                ui.checkbox(&mut form.y_up, "(plain CSV)");
                ui.end_row();
                field_ui(ui, "Minimum likelihood", &mut form.min_likelihood, "DeepLabCut");
            });
            if let Some(p) = problem.as_ref() {
                ui.colored_label(ui.visuals().error_fg_color, p);
            }
            ui.horizontal(|ui| {
                if ui.button("Open").clicked() {
                    match form.to_options() {
                        Ok((format, opts)) => {
                            *problem = None;
                            action = Some(ImportDialogAction::Open(format, opts));
                        }
                        Err(e) => *problem = Some(e),
                    }
                }
                if ui.button("Cancel").clicked() {
                    *problem = None;
                    action = Some(ImportDialogAction::Cancel);
                }
            });
        });
    action
}

fn field_ui(ui: &mut egui::Ui, label: &str, text: &mut String, hint: &str) {
    ui.label(label);
    ui.add(egui::TextEdit::singleline(text).hint_text(hint).desired_width(200.0));
    ui.end_row();
}
