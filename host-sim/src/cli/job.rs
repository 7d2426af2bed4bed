//! What the sharded commands (`--shard I/N`) put in a part's job besides numbers: the scenario
//! they ran, resolved so that `cimax merge` needs no file but the parts.

use serde::{Deserialize, Serialize};
use swarm_sim::scenario::Scenario;

/// A scenario as a job names it: a built-in one by name, a file by its path and its text (so
/// that a changed file makes another job, and the merge reads the very scenario the shards
/// ran).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ScenarioSource {
    /// The built-in name or the path, as given.
    pub name: String,
    /// The file's text; `None` for a built-in scenario.
    pub toml: Option<String>,
}

impl ScenarioSource {
    /// The scenario `name_or_path` names (a built-in name, else a file, which is read).
    ///
    /// # Errors
    /// If it is neither a built-in name nor a readable scenario file.
    pub fn of(name_or_path: &str) -> Result<ScenarioSource, String> {
        let toml = if Scenario::builtin(name_or_path).is_some() {
            None
        } else {
            // The loader's errors name the line, or the built-in scenarios.
            Scenario::load(name_or_path).map_err(|e| e.to_string())?;
            Some(
                std::fs::read_to_string(name_or_path)
                    .map_err(|e| format!("{name_or_path}: {e}"))?,
            )
        };
        Ok(ScenarioSource {
            name: name_or_path.to_string(),
            toml,
        })
    }

    /// The scenario.
    ///
    /// # Errors
    /// If the text does not parse (or the name is no longer built in).
    pub fn load(&self) -> Result<Scenario, String> {
        match &self.toml {
            None => Scenario::builtin(&self.name)
                .ok_or_else(|| format!("there is no built-in scenario {:?}", self.name)),
            Some(text) => Scenario::from_toml(text, &self.name).map_err(|e| e.to_string()),
        }
    }
}
