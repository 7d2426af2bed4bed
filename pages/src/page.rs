//! The generated pages' templates (`pages/templates/`, Jinja syntax) and their rendering.
//!
//! The templates are embedded with `include_str!` and parsed once, at the first page rendered;
//! the data comes as plain [`serde::Serialize`] structs built from the experiments' results.
//! Every number arrives formatted: the templates only place strings, so the pages stay byte
//! for byte what the Rust formatting makes of the numbers.
//!
//! Whitespace: `trim_blocks` and `lstrip_blocks` are on (a line holding only a `{% ... %}` tag
//! leaves nothing in the page) and a template's last newline is kept.

use std::sync::OnceLock;

use minijinja::{AutoEscape, Environment, UndefinedBehavior};

use crate::paper;
use serde::Serialize;

/// Every template by name (its path under `templates/`).
const TEMPLATES: &[(&str, &str)] = &[
    (
        "reliability.md.j2",
        include_str!("../templates/reliability.md.j2"),
    ),
    (
        "reliability/campaign.md.j2",
        include_str!("../templates/reliability/campaign.md.j2"),
    ),
    (
        "reliability/failing_seeds.md.j2",
        include_str!("../templates/reliability/failing_seeds.md.j2"),
    ),
    (
        "reliability/rules.md.j2",
        include_str!("../templates/reliability/rules.md.j2"),
    ),
    (
        "reliability/suite.md.j2",
        include_str!("../templates/reliability/suite.md.j2"),
    ),
    (
        "reliability/initiations.md.j2",
        include_str!("../templates/reliability/initiations.md.j2"),
    ),
    (
        "reliability/loss.md.j2",
        include_str!("../templates/reliability/loss.md.j2"),
    ),
    (
        "reliability/in_the_loop.md.j2",
        include_str!("../templates/reliability/in_the_loop.md.j2"),
    ),
    (
        "reproduction.md.j2",
        include_str!("../templates/reproduction.md.j2"),
    ),
    (
        "reproduction/setup.md.j2",
        include_str!("../templates/reproduction/setup.md.j2"),
    ),
    (
        "reproduction/comparison.md.j2",
        include_str!("../templates/reproduction/comparison.md.j2"),
    ),
    (
        "reproduction/sweep_table.md.j2",
        include_str!("../templates/reproduction/sweep_table.md.j2"),
    ),
    (
        "reproduction/waves.md.j2",
        include_str!("../templates/reproduction/waves.md.j2"),
    ),
    (
        "reproduction/sharp.md.j2",
        include_str!("../templates/reproduction/sharp.md.j2"),
    ),
    (
        "reproduction/gradient.md.j2",
        include_str!("../templates/reproduction/gradient.md.j2"),
    ),
    (
        "reproduction/cloud.md.j2",
        include_str!("../templates/reproduction/cloud.md.j2"),
    ),
    (
        "reproduction/cloud_caption.md.j2",
        include_str!("../templates/reproduction/cloud_caption.md.j2"),
    ),
    (
        "reproduction/cycle.md.j2",
        include_str!("../templates/reproduction/cycle.md.j2"),
    ),
    (
        "reproduction/course.md.j2",
        include_str!("../templates/reproduction/course.md.j2"),
    ),
    (
        "reproduction/sensitivity.md.j2",
        include_str!("../templates/reproduction/sensitivity.md.j2"),
    ),
    (
        "reproduction/shapes.md.j2",
        include_str!("../templates/reproduction/shapes.md.j2"),
    ),
    (
        "reproduction/settle.md.j2",
        include_str!("../templates/reproduction/settle.md.j2"),
    ),
    (
        "reproduction/beyond.md.j2",
        include_str!("../templates/reproduction/beyond.md.j2"),
    ),
    (
        "reproduction/speed.md.j2",
        include_str!("../templates/reproduction/speed.md.j2"),
    ),
];

/// The environment holding every template, built once.
fn environment() -> &'static Environment<'static> {
    static ENV: OnceLock<Environment<'static>> = OnceLock::new();
    ENV.get_or_init(|| {
        let mut env = Environment::new();
        env.set_trim_blocks(true);
        env.set_lstrip_blocks(true);
        env.set_keep_trailing_newline(true);
        env.set_auto_escape_callback(|_| AutoEscape::None);
        // A field the page does not have (renamed, misspelt, or never set) is an error, not a
        // blank in the page.
        env.set_undefined_behavior(UndefinedBehavior::Strict);
        // The paper's figure and section numbers, checked against its LaTeX source
        // (`crate::paper`): `{{ fig.sharp_sweep }}` is "Fig. 7", `{{ fign.sharp_sweep }}` "6",
        // `{{ sec.discussion }}` "§5". The templates type none in (a test below checks).
        env.add_global(
            "fig",
            minijinja::Value::from_serialize(paper::figure_names()),
        );
        env.add_global(
            "fign",
            minijinja::Value::from_serialize(
                paper::Fig::ALL
                    .iter()
                    .map(|f| (f.key(), f.number().to_string()))
                    .collect::<std::collections::BTreeMap<_, _>>(),
            ),
        );
        env.add_global(
            "sec",
            minijinja::Value::from_serialize(paper::section_names()),
        );
        for (name, source) in TEMPLATES {
            // The templates are part of the binary; one that does not parse is a bug that the
            // tests below catch.
            env.add_template(name, source)
                .unwrap_or_else(|e| panic!("template {name}: {e:#}"));
        }
        env
    })
}

/// Renders the template `name` with `context`.
///
/// # Errors
/// A [`RenderError`] with the template engine's error if `name` is unknown or the context
/// does not fit it.
pub fn render(name: &str, context: impl Serialize) -> Result<String, RenderError> {
    environment()
        .get_template(name)
        .and_then(|t| t.render(context))
        .map_err(|source| RenderError {
            template: name.to_string(),
            source,
        })
}

/// Why a template could not be rendered ([`render`]).
#[derive(Debug, thiserror::Error)]
#[error("template {template}: {source:#}")]
pub struct RenderError {
    /// The template's name.
    pub template: String,
    /// The template engine's error.
    pub source: minijinja::Error,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_template_parses() {
        let env = environment();
        for (name, _) in TEMPLATES {
            assert!(env.get_template(name).is_ok(), "{name}");
        }
    }

    #[test]
    fn tag_lines_leave_nothing_and_the_last_newline_stays() {
        let mut env = Environment::new();
        env.set_trim_blocks(true);
        env.set_lstrip_blocks(true);
        env.set_keep_trailing_newline(true);
        env.add_template("t", "a\n{% for x in xs %}\n- {{ x }}\n{% endfor %}\nb\n")
            .unwrap();
        let out = env
            .get_template("t")
            .unwrap()
            .render(minijinja::context! { xs => ["1", "2"] })
            .unwrap();
        assert_eq!(out, "a\n- 1\n- 2\nb\n");
    }

    #[test]
    fn no_template_types_in_a_figure_or_section_number_of_the_paper() {
        for (name, source) in TEMPLATES {
            for (k, _) in source.match_indices("Fig") {
                let after = source[k..]
                    .trim_start_matches("Figs")
                    .trim_start_matches("Fig");
                let after = after.trim_start_matches('.').trim_start();
                assert!(
                    !after.starts_with(|c: char| c.is_ascii_digit()),
                    "{name}: a figure number typed in: {}",
                    &source[k..(k + 12).min(source.len())]
                );
            }
            for (k, _) in source.match_indices('§') {
                assert!(
                    source[..k].ends_with("protocol.md "),
                    "{name}: a section number typed in (only docs/protocol.md's may be)"
                );
            }
        }
    }

    #[test]
    fn the_paper_s_numbers_come_from_the_latex_source() {
        let out = environment()
            .render_str(
                "{{ fig.sharp_run }}b, Figs. {{ fign.gradient_run }}–{{ fign.gradient_map }}, {{ sec.discussion }}",
                (),
            )
            .unwrap();
        assert_eq!(out, "Fig. 5b, Figs. 8–10, §5");
    }

    #[test]
    fn a_field_the_context_lacks_is_an_error_not_a_blank() {
        let err = render("reproduction.md.j2", minijinja::context! { seed => 1 })
            .unwrap_err()
            .to_string();
        assert!(err.contains("undefined"), "{err}");
    }
}
