//! A job's controls in a side-panel tab, the same for the fit and the diagnosis: while it runs,
//! its progress bar and Cancel ("Cancelling…" once asked); otherwise the button that starts it,
//! "… again" once it has a result.

use crate::session::Progress;
use eframe::egui::{self, RichText};

/// A job as its tab shows it.
pub struct JobView<'a> {
    /// What the button says ("Fit"), and what it does (on hover).
    pub name: &'a str,
    pub hover: &'a str,
    /// Its progress, while it runs.
    pub progress: Option<Progress>,
    /// Cancel was pressed and the job has not stopped yet.
    pub cancelling: bool,
    /// It has a result already.
    pub done: bool,
}

/// What the user pressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JobClick {
    None,
    Start,
    Cancel,
}

pub fn job_controls_ui(ui: &mut egui::Ui, job: JobView) -> JobClick {
    let Some(p) = job.progress else {
        let label = if job.done { format!("{} again", job.name) } else { job.name.to_string() };
        return if ui.button(label).on_hover_text(job.hover).clicked() {
            JobClick::Start
        } else {
            JobClick::None
        };
    };
    ui.add(egui::ProgressBar::new(p.fraction).text(RichText::new(p.text).small()).animate(true));
    let cancel = egui::Button::new(if job.cancelling { "Cancelling…" } else { "Cancel" });
    if ui.add_enabled(!job.cancelling, cancel).clicked() {
        JobClick::Cancel
    } else {
        JobClick::None
    }
}
