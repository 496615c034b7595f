//! A small valid scene as TOML text, to start a test from: a box, a plane terrain, one water
//! table, one sink and one spring. Tests add or replace what they are about.

use std::fmt::Write as _;

/// Scene text under construction.
#[derive(Debug, Clone)]
pub struct SceneText {
    head: String,
    sections: Vec<String>,
}

impl SceneText {
    /// Scene `name`, seed 1, domain [0, 0, 0] – [100, 100, 50], terrain a plane at 40 m,
    /// water table "wt" at 10 m, sink "a" at [10, 10, 40] and spring "s" at [90, 90, 10].
    pub fn new(name: &str) -> Self {
        SceneText {
            head: format!("name = \"{name}\"\nseed = 1\n"),
            sections: vec![
                "[domain]\nmin = [0, 0, 0]\nmax = [100, 100, 50]\n".into(),
                "[terrain]\nkind = \"plane\"\nelevation = 40\n".into(),
                "[[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n".into(),
                "[[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 40]\n".into(),
                "[[keypoints]]\nname = \"s\"\nkind = \"spring\"\nposition = [90, 90, 10]\nwater_table = \"wt\"\n"
                    .into(),
            ],
        }
    }

    /// Adds TOML at the end (a section, or more key points).
    pub fn with(mut self, toml: &str) -> Self {
        self.sections.push(format!("{}\n", toml.trim_end()));
        self
    }

    /// Replaces the section whose header line is `header` (e.g. `[terrain]`) by `toml`.
    pub fn replace(mut self, header: &str, toml: &str) -> Self {
        let at = self.sections.iter().position(|s| s.lines().next() == Some(header));
        let at = at.unwrap_or_else(|| panic!("SceneText has no section {header}"));
        self.sections[at] = format!("{}\n", toml.trim_end());
        self
    }

    /// The TOML text.
    pub fn text(&self) -> String {
        let mut text = self.head.clone();
        for s in &self.sections {
            let _ = writeln!(text, "{s}");
        }
        text
    }
}
