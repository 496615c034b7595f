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

    /// Sets the domain box.
    pub fn domain(self, min: [f64; 3], max: [f64; 3]) -> Self {
        let corner = |c: [f64; 3]| format!("[{}, {}, {}]", c[0], c[1], c[2]);
        self.replace("[domain]", &format!("[domain]\nmin = {}\nmax = {}", corner(min), corner(max)))
    }

    /// Makes the terrain a horizontal plane at `elevation`.
    pub fn plane(self, elevation: f64) -> Self {
        self.replace("[terrain]", &format!("[terrain]\nkind = \"plane\"\nelevation = {elevation}"))
    }

    /// Puts the water table "wt" at `elevation`.
    pub fn water_table(self, elevation: f64) -> Self {
        self.replace(
            "[[geology.water_tables]]",
            &format!("[[geology.water_tables]]\nname = \"wt\"\nelevation = {elevation}"),
        )
    }

    /// Replaces the sink and the spring by `sink` and `spring` (name, position); the spring
    /// still drains to "wt".
    pub fn sink_and_spring(mut self, sink: (&str, [f64; 3]), spring: (&str, [f64; 3])) -> Self {
        let at = |p: [f64; 3]| format!("[{}, {}, {}]", p[0], p[1], p[2]);
        let first = self.sections.iter().position(|s| s.starts_with("[[keypoints]]"));
        let first = first.expect("SceneText starts with its sink and spring");
        self.sections[first] =
            format!("[[keypoints]]\nname = \"{}\"\nkind = \"sink\"\nposition = {}\n", sink.0, at(sink.1));
        self.sections[first + 1] = format!(
            "[[keypoints]]\nname = \"{}\"\nkind = \"spring\"\nposition = {}\nwater_table = \"wt\"\n",
            spring.0,
            at(spring.1)
        );
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
