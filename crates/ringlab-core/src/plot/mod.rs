//! Figures without a plotting library: a raster of our own ([`canvas`]: antialiased lines,
//! bands, a bitmap [`font`]), charts on it ([`chart`]), written as PNG with the `png` crate
//! alone (the window draws its own plots; these are for reports).

pub mod canvas;
pub mod chart;
pub mod font;

pub use canvas::{Canvas, PlotError, Rgb};
pub use chart::{Axis, Chart};
