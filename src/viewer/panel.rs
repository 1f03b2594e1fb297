//! The side panel: method (preset and its parts, per half in the split view), render controls
//! and counters, display settings with the false-colour scale, live metrics, the pixel probe,
//! saving, and the hint to the keys.

use std::time::Instant;

use egui::{Color32, RichText, Ui};

use crate::display::{DisplayTransform, Transfer};
use crate::method::{BsdfSampling, EnvSampling, LightSampling, LightSelect, LobeSelection, Method, MicrofacetSampling, Preset, Sampler, TechniqueKind, TechniqueName, TriangleSampling};
use crate::scene::ApplicableOptions;

use crate::display::View;
use super::driver::Driver;

const ERROR_RED: Color32 = Color32::from_rgb(255, 110, 100);

/// A message shown in the panel for a few seconds (saves, errors of actions).
pub struct Notice {
    pub text: String,
    pub error: bool,
    pub since: Instant,
}

/// What the panel shows: the driver's slots and scene, and the window's settings.
pub struct PanelState<'a> {
    pub driver: &'a Driver,
    pub paused: bool,
    pub view: View,
    /// The views that make sense now (error views need a reference of the image's size).
    pub views: Vec<View>,
    pub display: DisplayTransform,
    /// Width and height fields (applied with their button).
    pub pending_size: (u32, u32),
    pub notice: Option<&'a Notice>,
}

/// What the user did in the panel this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    TogglePause,
    Reset,
    Save,
    Split(bool),
    /// A new method for a slot (slot 1: also the split view's second method from now on).
    Method(usize, Method),
    MaxDepth(u32),
    Size((u32, u32)),
    PendingSize((u32, u32)),
    View(View),
    Display(DisplayTransform),
}

/// Draws the panel of `state` and returns the user's actions.
pub fn show(state: &PanelState, ui: &mut Ui) -> Vec<Action> {
    let mut actions = Vec::new();
    let app = state;
    let actions_ref = &mut actions;
    egui::ScrollArea::vertical().show(ui, |ui| {
        let actions = actions_ref;
        ui.heading("pathlab view");
        ui.label(RichText::new("H: keys").weak());
        ui.separator();
        method_section(app, ui, actions);
        ui.separator();
        render_section(app, ui, actions);
        ui.separator();
        display_section(app, ui, actions);
        ui.separator();
        metrics_section(app, ui);
        ui.separator();
        if ui.button("Save EXR + PNG (S)").clicked() {
            actions.push(Action::Save);
        }
        if let Some(n) = app.notice {
            if n.since.elapsed().as_secs_f32() < 8.0 {
                ui.label(RichText::new(&n.text).color(if n.error { ERROR_RED } else { ui.visuals().text_color() }));
            }
        }
    });
    actions
}

/// A combo box over `options`, `name` labelling each; returns the new choice if changed.
fn choose<T: Copy + PartialEq>(ui: &mut Ui, id: impl std::hash::Hash + std::fmt::Debug, current: T, options: &[T], name: impl Fn(T) -> String) -> Option<T> {
    let mut chosen = current;
    egui::ComboBox::from_id_salt(id).width(180.0).selected_text(name(current)).show_ui(ui, |ui| {
        for &o in options {
            ui.selectable_value(&mut chosen, o, name(o));
        }
    });
    (chosen != current).then_some(chosen)
}

fn biased(name: &str, is_biased: bool) -> String {
    if is_biased { format!("{name} (BIASED demo)") } else { name.to_string() }
}

fn method_section(app: &PanelState, ui: &mut Ui, actions: &mut Vec<Action>) {
    let split = app.driver.slots.len() > 1;
    let mut want_split = split;
    ui.checkbox(&mut want_split, "Split view: two methods at equal time");
    if want_split != split {
        actions.push(Action::Split(want_split));
    }
    let has = ApplicableOptions::of_scene(&app.driver.scene);
    for i in 0..app.driver.slots.len() {
        let method = app.driver.slots[i].method;
        if app.driver.slots.len() > 1 {
            ui.label(RichText::new(if i == 0 { "Left" } else { "Right" }).strong());
        }
        let mut next: Option<Method> = None;
        egui::Grid::new(("method", i)).num_columns(2).show(ui, |ui| {
            ui.label("preset");
            let presets: Vec<Option<Preset>> = Preset::ALL.iter().copied().map(Some).chain([None]).collect();
            let label = |p: Option<Preset>| p.map_or_else(|| "custom".to_string(), |p| p.name().to_string());
            if let Some(Some(p)) = choose(ui, ("preset", i), method.preset(), &presets, label) {
                next = Some(p.method());
            }
            ui.end_row();
            ui.label("sampler");
            if let Some(s) = choose(ui, ("sampler", i), method.sampler, &Sampler::ALL, |s: Sampler| s.name().to_string()) {
                next = Some(Method { sampler: s, ..method });
            }
            ui.end_row();
            ui.label("bsdf");
            if let Some(b) = choose(ui, ("bsdf", i), method.bsdf, &BsdfSampling::ALL, |b: BsdfSampling| biased(b.name(), b.is_biased())) {
                next = Some(Method { bsdf: b, ..method });
            }
            ui.end_row();
            ui.label("lights");
            if let Some(l) = choose(ui, ("lights", i), method.lights, &LightSampling::ALL, |l: LightSampling| biased(l.name(), l.is_biased())) {
                next = Some(Method { lights: l, ..method });
            }
            ui.end_row();
            // The finer options only where they can change this scene's image: shown where the
            // scene can use them, enabled where the method does.
            let can = has.with_method(&method);
            if has.light_select {
                ui.label("light select");
                let selects: Vec<Option<LightSelect>> = [None].into_iter().chain(LightSelect::ALL.map(Some)).collect();
                let select_label = |s: Option<LightSelect>| s.map_or_else(|| "scene default".to_string(), |s| s.name().to_string());
                if let Some(select) = ui.add_enabled_ui(can.light_select, |ui| choose(ui, ("select", i), method.select, &selects, select_label)).inner {
                    next = Some(Method { select, ..method });
                }
                ui.end_row();
            }
            if has.triangle_sampling {
                ui.label("triangles");
                let name = |t: TriangleSampling| t.name().to_string();
                if let Some(t) = ui.add_enabled_ui(can.triangle_sampling, |ui| choose(ui, ("triangles", i), method.triangles, &TriangleSampling::ALL, name)).inner {
                    next = Some(Method { triangles: t, ..method });
                }
                ui.end_row();
            }
            if has.microfacet_sampling {
                ui.label("microfacets");
                let name = |m: MicrofacetSampling| m.name().to_string();
                if let Some(m) = ui.add_enabled_ui(can.microfacet_sampling, |ui| choose(ui, ("microfacets", i), method.microfacet, &MicrofacetSampling::ALL, name)).inner {
                    next = Some(Method { microfacet: m, ..method });
                }
                ui.end_row();
            }
            if has.lobe_selection {
                ui.label("lobes");
                let name = |l: LobeSelection| l.name().to_string();
                if let Some(l) = ui.add_enabled_ui(can.lobe_selection, |ui| choose(ui, ("lobes", i), method.lobes, &LobeSelection::ALL, name)).inner {
                    next = Some(Method { lobes: l, ..method });
                }
                ui.end_row();
            }
            if has.environment_sampling {
                ui.label("environment");
                let mut sampled = method.environment;
                let changed = ui.add_enabled_ui(can.environment_sampling, |ui| ui.checkbox(&mut sampled, "sampled by NEE").changed()).inner;
                if changed {
                    next = Some(Method { environment: sampled, ..method });
                }
                ui.end_row();
            }
            if has.env_sampling {
                ui.label("environment map");
                let name = |e: EnvSampling| e.name().to_string();
                if let Some(e) = ui.add_enabled_ui(can.env_sampling, |ui| choose(ui, ("env", i), method.env_sampling, &EnvSampling::ALL, name)).inner {
                    next = Some(Method { env_sampling: e, ..method });
                }
                ui.end_row();
            }
            // Researchers' techniques (`--technique`), where one of the kind is loaded.
            for kind in TechniqueKind::ALL {
                let loaded = app.driver.scene.techniques.iter().filter(|t| t.kind == kind).map(|t| Some(t.name));
                let options: Vec<Option<TechniqueName>> = [None].into_iter().chain(loaded).collect();
                if options.len() < 2 {
                    continue;
                }
                ui.label(format!("{} technique", kind.name()));
                let current = match kind {
                    TechniqueKind::Bsdf => method.bsdf_technique,
                    TechniqueKind::Light => method.light_technique,
                    TechniqueKind::Env => method.env_technique,
                };
                let label = |n: Option<TechniqueName>| n.map_or_else(|| "built-in".to_string(), |n| n.to_string());
                if let Some(choice) = choose(ui, ("technique", kind.name(), i), current, &options, label) {
                    next = Some(match kind {
                        TechniqueKind::Bsdf => Method { bsdf_technique: choice, ..method },
                        TechniqueKind::Light => Method { light_technique: choice, ..method },
                        TechniqueKind::Env => Method { env_technique: choice, environment: method.environment || choice.is_some(), ..method },
                    });
                }
                ui.end_row();
            }
        });
        if method.is_biased() {
            ui.label(RichText::new("biased on purpose: it converges to the wrong image").color(ERROR_RED));
        }
        if let Some(m) = next {
            actions.push(Action::Method(i, m));
        }
    }
}

fn render_section(app: &PanelState, ui: &mut Ui, actions: &mut Vec<Action>) {
    ui.horizontal(|ui| {
        if ui.button(if app.paused { "Resume (Space)" } else { "Pause (Space)" }).clicked() {
            actions.push(Action::TogglePause);
        }
        if ui.button("Reset (R)").clicked() {
            actions.push(Action::Reset);
        }
    });
    egui::Grid::new("counters").num_columns(2).show(ui, |ui| {
        for slot in &app.driver.slots {
            ui.label(RichText::new(slot.method.name()).strong());
            ui.label(format!(
                "{} spp   {:.2} s   {:.2} M samples/s",
                slot.spp(),
                slot.seconds,
                slot.samples_per_second() / 1e6
            ));
            ui.end_row();
        }
    });
    let mut depth = app.driver.scene.render.max_depth;
    let mut size = app.pending_size;
    egui::Grid::new("scene settings").num_columns(2).show(ui, |ui| {
        ui.label("max_depth");
        if ui.add(egui::DragValue::new(&mut depth).range(1..=64)).changed() {
            actions.push(Action::MaxDepth(depth));
        }
        ui.end_row();
        ui.label("resolution");
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut size.0).range(8..=4096));
            ui.label("x");
            ui.add(egui::DragValue::new(&mut size.1).range(8..=4096));
            let current = (app.driver.scene.render.width, app.driver.scene.render.height);
            if ui.add_enabled(size != current, egui::Button::new("apply")).clicked() {
                actions.push(Action::Size(size));
            }
        });
        ui.end_row();
    });
    if size != app.pending_size {
        actions.push(Action::PendingSize(size));
    }
}

fn display_section(app: &PanelState, ui: &mut Ui, actions: &mut Vec<Action>) {
    egui::Grid::new("display").num_columns(2).show(ui, |ui| {
        ui.label("view (V)");
        if let Some(v) = choose(ui, "view", app.view, &app.views, |v: View| v.label().to_string()) {
            actions.push(Action::View(v));
        }
        ui.end_row();
        ui.label("exposure");
        let mut display = app.display;
        ui.add(egui::Slider::new(&mut display.exposure, -8.0..=8.0).suffix(" stops").step_by(0.1));
        ui.end_row();
        ui.label("transform");
        ui.horizontal(|ui| {
            let is_gamma = matches!(display.transfer, Transfer::Gamma(_));
            if ui.selectable_label(!is_gamma, "sRGB").clicked() {
                display.transfer = Transfer::Srgb;
            }
            if ui.selectable_label(is_gamma, "gamma").clicked() && !is_gamma {
                display.transfer = Transfer::Gamma(2.2);
            }
            if let Transfer::Gamma(g) = &mut display.transfer {
                ui.add(egui::DragValue::new(g).range(0.2..=5.0).speed(0.01));
            }
        });
        ui.end_row();
        if display != app.display {
            actions.push(Action::Display(display));
        }
    });
    if app.view != View::Radiance {
        colour_bar(ui, app.view);
    }
    if app.driver.reference().is_some() && !app.driver.reference_matches() {
        let r = app.driver.reference().map(|r| (r.width, r.height)).unwrap_or_default();
        ui.label(RichText::new(format!("the reference is {}x{}: error views and metrics need that size", r.0, r.1)).color(ERROR_RED));
    }
}

/// The false-colour scale of `view`: magma from 10^lo to 10^hi.
fn colour_bar(ui: &mut Ui, view: View) {
    let (lo, hi) = view.log10_range();
    let (rect, _) = ui.allocate_exact_size(egui::vec2(260.0, 14.0), egui::Sense::hover());
    let steps = 64;
    for k in 0..steps {
        let t = k as f32 / (steps - 1) as f32;
        let [r, g, b] = crate::figures::colormap::magma_at(t as f64);
        let x0 = rect.min.x + rect.width() * k as f32 / steps as f32;
        let x1 = rect.min.x + rect.width() * (k + 1) as f32 / steps as f32;
        ui.painter().rect_filled(egui::Rect::from_x_y_ranges(x0..=x1, rect.y_range()), 0.0, Color32::from_rgb(r, g, b));
    }
    ui.horizontal(|ui| {
        ui.label(format!("1e{lo}"));
        ui.add_space(170.0);
        ui.label(format!("1e{hi}"));
    });
    ui.label(RichText::new(format!("{} (log scale)", view.label())).weak());
}

fn metrics_section(app: &PanelState, ui: &mut Ui) {
    let with_reference = app.driver.reference_matches();
    ui.label(RichText::new(if with_reference { "Metrics against the reference" } else { "Estimated error (no reference)" }).strong());
    egui::Grid::new("metrics").num_columns(2).show(ui, |ui| {
        for slot in &app.driver.slots {
            ui.label(slot.method.name());
            match slot.latest {
                Some(p) if !p.estimated => {
                    ui.label(format!("PSNR {:.2} dB  SSIM {:.4}\nrelMSE {:.3e}  ({} spp)", p.psnr, p.ssim.unwrap_or(f64::NAN), p.rel_mse, p.spp));
                }
                Some(p) => {
                    ui.label(format!("est. PSNR {:.2} dB\nest. relMSE {:.3e}  ({} spp)", p.psnr, p.rel_mse, p.spp));
                }
                None => {
                    ui.label("…");
                }
            }
            ui.end_row();
        }
    });
    if let Some(p) = app.driver.probe.filter(|p| p.slot < app.driver.slots.len()) {
        ui.separator();
        ui.label(RichText::new(format!("pixel ({}, {}), {} spp", p.x, p.y, p.spp)).strong());
        ui.monospace(format!("mean   {:.4} {:.4} {:.4}", p.mean[0], p.mean[1], p.mean[2]));
        ui.monospace(format!("stderr {:.4} {:.4} {:.4}", p.stderr[0], p.stderr[1], p.stderr[2]));
    }
}
