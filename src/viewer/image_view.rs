//! The image area: the shown texture fitted to the space (integer zoom when it fits, nearest
//! filtering), the split view's two halves and draggable divider, method labels, the mouse-over
//! pixel probe, and the banner of a failed scene reload over the last good image.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Ui};

use super::driver::Driver;

/// Background of the reload-error banner.
pub const BANNER_RED: Color32 = Color32::from_rgb(150, 20, 20);

/// Where an image of `size` pixels goes in `avail` (points), keeping its aspect ratio.
fn fit(avail: Rect, size: (u32, u32), pixels_per_point: f32) -> Rect {
    let (w, h) = (size.0 as f32 / pixels_per_point, size.1 as f32 / pixels_per_point);
    let mut scale = (avail.width() / w).min(avail.height() / h);
    if scale >= 1.0 {
        scale = scale.floor();
    }
    Rect::from_center_size(avail.center(), egui::vec2(w * scale, h * scale))
}

/// What the image area drew and what the user did there.
#[derive(Debug, Clone, Copy)]
pub struct ImageResponse {
    /// Where the image is (points).
    pub image_rect: Rect,
    /// The split view's divider: its place as a fraction of the width (moved by a drag) and its x.
    pub divider: f32,
    pub divider_x: Option<f32>,
    /// The pixel under the pointer: (slot, x, y).
    pub probe: Option<(usize, u32, u32)>,
}

/// Draws the driver's shown images (split at `divider` when it has two slots) and the banner of
/// `scene_error`.
pub fn show(driver: &Driver, divider: f32, scene_error: Option<&str>, ui: &mut Ui) -> ImageResponse {
    let avail = ui.available_rect_before_wrap();
    let size = (driver.scene.render.width, driver.scene.render.height);
    let rect = fit(avail, size, ui.ctx().pixels_per_point());
    let mut out = ImageResponse { image_rect: rect, divider, divider_x: None, probe: None };
    let response = ui.allocate_rect(avail, Sense::click_and_drag());
    let painter = ui.painter_at(avail);
    let full_uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
    let split = driver.slots.len() > 1;

    if !split {
        if let Some(id) = driver.slots.first().and_then(|s| s.texture_id) {
            painter.image(id, rect, full_uv, Color32::WHITE);
        }
    } else {
        // Drag anywhere on the image to move the divider.
        if response.dragged() {
            if let Some(p) = response.interact_pointer_pos() {
                out.divider = ((p.x - rect.min.x) / rect.width()).clamp(0.0, 1.0);
            }
        }
        let f = out.divider;
        let x = rect.min.x + f * rect.width();
        let halves = [
            (Rect::from_min_max(rect.min, Pos2::new(x, rect.max.y)), Rect::from_min_max(Pos2::ZERO, Pos2::new(f, 1.0))),
            (Rect::from_min_max(Pos2::new(x, rect.min.y), rect.max), Rect::from_min_max(Pos2::new(f, 0.0), Pos2::new(1.0, 1.0))),
        ];
        for (slot, (r, uv)) in driver.slots.iter().zip(halves) {
            if let Some(id) = slot.texture_id {
                painter.image(id, r, uv, Color32::WHITE);
            }
        }
        painter.line_segment([Pos2::new(x, rect.min.y), Pos2::new(x, rect.max.y)], Stroke::new(2.0, Color32::WHITE));
        painter.circle_filled(Pos2::new(x, rect.center().y), 6.0, Color32::WHITE);
        out.divider_x = Some(x);
        // Which method is which.
        let font = FontId::proportional(14.0);
        painter.text(rect.left_top() + egui::vec2(6.0, 4.0), Align2::LEFT_TOP, driver.slots[0].method.name(), font.clone(), Color32::WHITE);
        painter.text(rect.right_top() + egui::vec2(-6.0, 4.0), Align2::RIGHT_TOP, driver.slots[1].method.name(), font, Color32::WHITE);
    }

    // Mouse-over probe: the pixel under the pointer, of the half it is in.
    if let Some(p) = response.hover_pos().filter(|p| rect.contains(*p)) {
        let u = (p.x - rect.min.x) / rect.width();
        let v = (p.y - rect.min.y) / rect.height();
        let x = ((u * size.0 as f32) as u32).min(size.0 - 1);
        let y = ((v * size.1 as f32) as u32).min(size.1 - 1);
        let slot = usize::from(split && u > out.divider);
        out.probe = Some((slot, x, y));
    }

    if let Some(error) = scene_error {
        let banner = Rect::from_min_size(avail.min, egui::vec2(avail.width(), 70.0));
        painter.rect_filled(banner, 0.0, BANNER_RED);
        painter.text(
            banner.min + egui::vec2(8.0, 6.0),
            Align2::LEFT_TOP,
            format!("scene reload failed; showing the last good image\n{}", first_lines(error, 3)),
            FontId::monospace(12.0),
            Color32::WHITE,
        );
    }
    out
}

fn first_lines(text: &str, n: usize) -> String {
    text.lines().take(n).collect::<Vec<_>>().join("\n")
}
