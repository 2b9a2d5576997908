//! On a software rasteriser, the frame's egui shapes are handed to our own lean pipeline
//! ([`crate::render::ui_painter`]) instead of egui-wgpu's: see there for why. Call
//! [`hand_over`] at the very end of a frame's UI; shapes painted after it stay with egui.

use crate::render::ui_painter::{AtlasCopy, UiBatch, batch_callback};
use eframe::egui::{self, LayerId, Shape, epaint::ClippedShape, layers::ShapeIdx};
use std::sync::Arc;

fn enabled_id() -> egui::Id {
    egui::Id::unique("ringlab-lean-paint")
}

fn atlas_id() -> egui::Id {
    egui::Id::unique("ringlab-lean-paint-atlas")
}

fn last_batch_id() -> egui::Id {
    egui::Id::unique("ringlab-lean-paint-batch")
}

/// Turns the hand-over on or off for `ctx`: on only where [`crate::render::callback::install`]
/// put the painter into the renderer's callback resources (otherwise nothing would be drawn).
pub fn set_enabled(ctx: &egui::Context, on: bool) {
    ctx.data_mut(|d| d.insert_temp(enabled_id(), on));
}

pub fn is_enabled(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(enabled_id())).unwrap_or(false)
}

/// The batch the last [`hand_over`] made (for counting what it asks of the rasteriser).
pub fn last_batch(ctx: &egui::Context) -> Option<Arc<UiBatch>> {
    ctx.data(|d| d.get_temp::<Arc<UiBatch>>(last_batch_id()))
}

/// Whether our pipeline can draw `shape`: a mesh of the font atlas (everything egui's widgets
/// and plots draw); images and paint callbacks stay with egui.
fn drawable(shape: &Shape) -> bool {
    match shape {
        Shape::Vec(v) => v.iter().all(drawable),
        Shape::Callback(_) => false,
        s => s.texture_id() == egui::TextureId::default(),
    }
}

/// The font atlas as it is now, the same `Arc` as last frame's when nothing changed (the
/// painter uploads it again only when the `Arc` changes). Copying and comparing its megabyte
/// or two costs a few tenths of a millisecond; it only changes when new glyphs are drawn.
fn atlas(ctx: &egui::Context) -> Arc<AtlasCopy> {
    let last = ctx.data(|d| d.get_temp::<Arc<AtlasCopy>>(atlas_id()));
    let image = ctx.fonts(|f| f.image());
    let current = match last {
        Some(a) if a.size == image.size && a.pixels == image.pixels => a,
        _ => Arc::new(AtlasCopy { size: image.size, pixels: image.pixels }),
    };
    ctx.data_mut(|d| d.insert_temp(atlas_id(), current.clone()));
    current
}

/// Moves the shapes of this frame's layers that [`drawable`] accepts into one batch drawn by
/// paint callbacks put where each stretch of them began, so the order of drawing is kept.
pub fn hand_over(ctx: &egui::Context) {
    if !is_enabled(ctx) {
        return;
    }
    let mut layers = vec![LayerId::background()];
    layers.extend(
        ctx.memory(|m| m.layer_ids().filter(|l| *l != LayerId::background()).collect::<Vec<_>>()),
    );
    // A layer moved as a whole (egui's transforms) is transformed after the frame: not ours.
    layers.retain(|l| ctx.layer_transform_to_global(*l).is_none());

    // (layer, index of the stretch's first shape, its shapes)
    let mut stretches: Vec<(LayerId, usize, Vec<ClippedShape>)> = Vec::new();
    ctx.graphics_mut(|g| {
        for &layer in &layers {
            let Some(list) = g.get_mut(layer) else { continue };
            let mut current: Option<(usize, Vec<ClippedShape>)> = None;
            for i in 0..list.next_idx().0 {
                // Some(shape): ours now; None: an empty slot (keeps the stretch going); Err: one
                // that stays with egui (a callback such as our 3D view, or an image) ends it.
                let mut taken: Result<Option<ClippedShape>, ()> = Err(());
                list.mutate_shape(ShapeIdx(i), |c| {
                    if matches!(c.shape, Shape::Noop) {
                        taken = Ok(None);
                    } else if drawable(&c.shape) {
                        let shape = std::mem::replace(&mut c.shape, Shape::Noop);
                        taken = Ok(Some(ClippedShape { shape, ..c.clone() }));
                    }
                });
                match taken {
                    Ok(Some(s)) => current.get_or_insert_with(|| (i, Vec::new())).1.push(s),
                    Ok(None) => {}
                    Err(()) => {
                        if let Some((start, shapes)) = current.take() {
                            stretches.push((layer, start, shapes));
                        }
                    }
                }
            }
            if let Some((start, shapes)) = current {
                stretches.push((layer, start, shapes));
            }
        }
    });
    if stretches.is_empty() {
        return;
    }
    let ppp = ctx.pixels_per_point();
    let mut places = Vec::with_capacity(stretches.len());
    let mut runs = Vec::with_capacity(stretches.len());
    for (layer, start, shapes) in stretches {
        places.push((layer, start));
        runs.push(ctx.tessellate(shapes, ppp));
    }
    let batch = Arc::new(UiBatch { runs, atlas: atlas(ctx) });
    let screen = ctx.viewport_rect();
    ctx.graphics_mut(|g| {
        for (run, (layer, start)) in places.into_iter().enumerate() {
            let cb = batch_callback(batch.clone(), run, screen);
            g.entry(layer).set(ShapeIdx(start), screen, Shape::Callback(cb));
        }
    });
    ctx.data_mut(|d| d.insert_temp(last_batch_id(), batch));
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::{Color32, PaintCallback, Rect, pos2, vec2};

    /// A stand-in for the 3D view's callback (not ours to draw).
    fn view3d() -> Shape {
        Shape::Callback(PaintCallback {
            rect: Rect::from_min_size(pos2(10.0, 10.0), vec2(50.0, 50.0)),
            callback: Arc::new(7u32),
        })
    }

    /// What each shape of a frame's output is, in drawing order: "lean" (our callback), "3d"
    /// (the stand-in) or "egui" (left to egui-wgpu); empty slots left out.
    fn callbacks(shapes: &[ClippedShape]) -> Vec<&'static str> {
        shapes
            .iter()
            .filter_map(|c| match &c.shape {
                Shape::Callback(cb) if cb.callback.downcast_ref::<u32>().is_some() => Some("3d"),
                Shape::Callback(_) => Some("lean"),
                Shape::Noop => None,
                _ => Some("egui"),
            })
            .collect()
    }

    fn frame(ctx: &egui::Context) -> Vec<ClippedShape> {
        ctx.run_ui(egui::RawInput::default(), |ui| {
            ui.label("before");
            ui.painter().rect_filled(
                Rect::from_min_size(pos2(0.0, 0.0), vec2(5.0, 5.0)),
                0.0,
                Color32::RED,
            );
            ui.painter().add(view3d());
            ui.label("after");
            hand_over(ui.ctx());
        })
        .shapes
    }

    #[test]
    fn shapes_go_to_the_lean_painter_around_other_callbacks_in_their_order() {
        let ctx = egui::Context::default();
        // Off: egui draws everything.
        let off = frame(&ctx);
        assert!(callbacks(&off).iter().all(|c| *c != "lean"));
        assert!(last_batch(&ctx).is_none());

        set_enabled(&ctx, true);
        let on = frame(&ctx);
        assert_eq!(callbacks(&on), ["lean", "3d", "lean"]);
        let batch = last_batch(&ctx).expect("a batch");
        assert_eq!(batch.runs.len(), 2, "one run before the 3D view, one after");
        assert!(batch.runs.iter().all(|r| !r.is_empty()));
        assert!(
            batch.atlas.size[0] > 0
                && batch.atlas.pixels.len() == batch.atlas.size[0] * batch.atlas.size[1]
        );

        // Nothing new drawn: the same atlas, so the painter does not upload it again.
        let first = batch.atlas.clone();
        frame(&ctx);
        let again = last_batch(&ctx).expect("a batch");
        assert!(Arc::ptr_eq(&first, &again.atlas));
    }
}
