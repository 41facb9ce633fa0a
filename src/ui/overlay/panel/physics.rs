//! The panel's physics section: the stage switches and the settings the
//! window applies live.

use bevy_egui::egui;

use crate::resources::{
    AUTO_TREE_FROM, CollisionDetection, DEFAULT_THETA, FragmentSizes, GravityMethod, Integrator, SimulationSettings,
};
use crate::ui::session::{FRAGMENT_SPREAD_RANGE, MAX_BODIES_RANGE, MIN_FRAGMENT_SIZE_RANGE};
use crate::ui::widgets::slider;

pub(super) fn physics(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.label("Stages");
    ui.checkbox(&mut settings.stages.gravity, "gravity");
    gravity_method(ui, settings);
    ui.horizontal(|ui| {
        ui.label("integrator");
        ui.radio_value(&mut settings.integrator, Integrator::Leapfrog, "leapfrog")
            .on_hover_text("drift–kick–drift, second order: orbits stay round");
        ui.radio_value(
            &mut settings.integrator,
            Integrator::SemiImplicitEuler,
            "semi-implicit Euler",
        )
        .on_hover_text("the thesis: kick, then drift; first order, orbits swing by a few % of their radius");
    });
    ui.checkbox(&mut settings.stages.collisions, "collision detection");
    ui.add_enabled_ui(settings.stages.collisions, |ui| {
        ui.horizontal(|ui| {
            ui.radio_value(&mut settings.collision_detection, CollisionDetection::Swept, "swept")
                .on_hover_text("along each body's path over the update: fast bodies cannot pass through one another");
            ui.radio_value(
                &mut settings.collision_detection,
                CollisionDetection::Discrete,
                "discrete",
            )
            .on_hover_text("the thesis: only where the update ends; bodies faster than their size may tunnel");
        });
    });
    ui.add_enabled(
        settings.stages.collisions,
        egui::Checkbox::new(
            &mut settings.stages.collision_response,
            "collision response (bounce, shatter)",
        ),
    );
    ui.add(slider(&mut settings.shatter_fragments, 2..=20).text("shatter fragments"));
    fragment_sizes(ui, settings);
    ui.add(
        slider(&mut settings.shatter_threshold, 0.0..=50.0)
            .logarithmic(true)
            .text("impact threshold"),
    );
    ui.add(
        slider(&mut settings.min_fragment_size, MIN_FRAGMENT_SIZE_RANGE)
            .logarithmic(true)
            .text("smallest fragment"),
    )
    .on_hover_text("edge length: a collision whose fragments would be smaller bounces (0: no floor, the thesis)");
    ui.add(
        slider(&mut settings.max_bodies, MAX_BODIES_RANGE)
            .logarithmic(true)
            .text("body budget"),
    )
    .on_hover_text("a shatter that would make more bodies bounces");
    ui.add(slider(&mut settings.fragment_spread, FRAGMENT_SPREAD_RANGE).text("fragment spread"))
        .on_hover_text("the fragments' speed apart, as a share of the impact speed (the thesis's \"Streuung\")");
}

/// How gravity is summed: auto, direct, or the tree and its θ.
fn gravity_method(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.horizontal(|ui| {
        let method = settings.gravity_method;
        if ui
            .radio(method == GravityMethod::Auto, "auto")
            .on_hover_text(format!(
                "the direct sum below {AUTO_TREE_FROM} sources, else the tree at θ {DEFAULT_THETA}"
            ))
            .clicked()
        {
            settings.gravity_method = GravityMethod::Auto;
        }
        if ui.radio(method == GravityMethod::Direct, "direct sum").clicked() {
            settings.gravity_method = GravityMethod::Direct;
        }
        let tree = matches!(method, GravityMethod::Tree { .. });
        if ui
            .radio(tree, "tree")
            .on_hover_text("Barnes–Hut: for thousands of sources")
            .clicked()
            && !tree
        {
            settings.gravity_method = GravityMethod::Tree { theta: DEFAULT_THETA };
        }
        if let GravityMethod::Tree { theta } = &mut settings.gravity_method {
            ui.add(slider(theta, 0.0..=1.5).text("θ"))
                .on_hover_text("opening angle: 0 is the direct sum; 0.5 errs about 0.1 %");
        }
    });
}

/// How a shatter sizes its fragments: equal, or the power law and its α.
fn fragment_sizes(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.horizontal(|ui| {
        ui.label("sizes");
        let sizes = settings.fragment_sizes;
        if ui
            .radio(sizes == FragmentSizes::Equal, "equal")
            .on_hover_text("the thesis: equal cubes that keep the pair's volume")
            .clicked()
        {
            settings.fragment_sizes = FragmentSizes::Equal;
        }
        let law = matches!(sizes, FragmentSizes::PowerLaw { .. });
        if ui
            .radio(law, "power law")
            .on_hover_text("the NASA standard breakup model: N(>L) ∝ L^−α, at most the fragments above")
            .clicked()
            && !law
        {
            settings.fragment_sizes = FragmentSizes::PowerLaw { exponent: 1.71 };
        }
        if let FragmentSizes::PowerLaw { exponent } = &mut settings.fragment_sizes {
            ui.add(slider(exponent, 0.5..=3.0).text("α"))
                .on_hover_text("1.71 for collisions, 1.6 for explosions");
        }
    });
}
