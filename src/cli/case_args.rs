//! Flags shared by every command that runs the model: which case, and overrides of it.

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::config::{Case, CaseFile, load_case_file, load_preset};
use std::path::PathBuf;

#[derive(Args, Debug, Clone, Default)]
pub struct CaseArgs {
    /// A preset from crates/ringlab-core/assets/presets (see `ringlab presets`); default paper-ring
    #[arg(long, conflicts_with = "config")]
    pub preset: Option<String>,
    /// A case file in the presets' TOML format
    #[arg(long, value_name = "FILE.toml")]
    pub config: Option<PathBuf>,
    /// Drag coefficient C1 (about e1, the line of nodes; dimensionless)
    #[arg(long, allow_negative_numbers = true)]
    pub c1: Option<f64>,
    /// Drag coefficient C2 (about e2, the symmetry axis)
    #[arg(long, allow_negative_numbers = true)]
    pub c2: Option<f64>,
    /// Drag coefficient C3 (about e3)
    #[arg(long, allow_negative_numbers = true)]
    pub c3: Option<f64>,
    /// Initial tilt theta (rad; 0 upright, pi/2 flat)
    #[arg(long, allow_negative_numbers = true)]
    pub theta0: Option<f64>,
    /// Initial theta' (rad per time unit)
    #[arg(long, allow_negative_numbers = true)]
    pub thetadot0: Option<f64>,
    /// Initial precession rate phi' (rad per time unit)
    #[arg(long, allow_negative_numbers = true)]
    pub phidot0: Option<f64>,
    /// Initial spin rate psi' (rad per time unit)
    #[arg(long, allow_negative_numbers = true)]
    pub psidot0: Option<f64>,
    /// Initial heading phi (rad)
    #[arg(long, allow_negative_numbers = true)]
    pub phi0: Option<f64>,
    /// Static friction coefficient for the validity check
    #[arg(long, allow_negative_numbers = true)]
    pub mu: Option<f64>,
    /// End time (in the case's time unit)
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Output spacing
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Relative tolerance of the integrator
    #[arg(long, allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance of the integrator
    #[arg(long, allow_negative_numbers = true)]
    pub atol: Option<f64>,
}

impl CaseArgs {
    /// The case file with every override applied (not yet validated as a whole).
    pub fn case_file(&self) -> Result<CaseFile> {
        let mut f = match (&self.preset, &self.config) {
            (Some(_), Some(_)) => bail!("give either --preset or --config, not both"),
            (_, Some(path)) => load_case_file(path)?,
            (Some(name), None) => load_preset(name)?,
            (None, None) => load_preset("paper-ring")?,
        };
        let set = |slot: &mut f64, v: Option<f64>, flag: &str| -> Result<()> {
            if let Some(v) = v {
                if !v.is_finite() {
                    bail!("{flag} = {v}: must be a finite number");
                }
                *slot = v;
            }
            Ok(())
        };
        set(&mut f.drag.c[0], self.c1, "--c1")?;
        set(&mut f.drag.c[1], self.c2, "--c2")?;
        set(&mut f.drag.c[2], self.c3, "--c3")?;
        set(&mut f.initial.theta, self.theta0, "--theta0")?;
        set(&mut f.initial.theta_dot, self.thetadot0, "--thetadot0")?;
        set(&mut f.initial.phi_dot, self.phidot0, "--phidot0")?;
        set(&mut f.initial.psi_dot, self.psidot0, "--psidot0")?;
        set(&mut f.initial.phi, self.phi0, "--phi0")?;
        set(&mut f.run.mu, self.mu, "--mu")?;
        set(&mut f.run.t_end, self.t_end, "--t-end")?;
        set(&mut f.run.dt, self.dt, "--dt")?;
        set(&mut f.run.rtol, self.rtol, "--rtol")?;
        set(&mut f.run.atol, self.atol, "--atol")?;
        Ok(f)
    }

    /// The validated case.
    pub fn case(&self) -> Result<Case> {
        let f = self.case_file()?;
        let name = f.name.clone();
        f.build()
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("case '{name}' with the given flags"))
    }
}
