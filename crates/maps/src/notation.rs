//! How an atlas's parameters are written for readers: their symbols (`ω`) and
//! long names (`forcing frequency`), from the scene, kept in [`Meta`] so that
//! files and figures name the axes the same way.

use crate::atlas::Meta;

/// How one parameter is written: what the scene declares for it, or what its
/// name gives ([`scene::Scene::symbol`], [`scene::Scene::long_name`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Notation {
    /// The parameter's name (`omega`).
    pub name: String,
    /// Its symbol (`ω`).
    pub symbol: String,
    /// What it is, in a few words (`forcing frequency`), when the scene says.
    pub long_name: Option<String>,
}

impl Notation {
    /// The notation of every parameter of `scene`, in the scene's order.
    pub fn of_scene(scene: &scene::Scene) -> Vec<Notation> {
        scene
            .parameter_names()
            .iter()
            .map(|name| Notation {
                name: name.clone(),
                symbol: scene.symbol(name),
                long_name: scene.long_name(name).map(str::to_string),
            })
            .collect()
    }
}

impl Meta {
    /// The symbol of parameter `name` (an axis or any parameter of the
    /// scene), to label figures: the one stored with the atlas (declared in
    /// its scene, `symbol = "ω"`), else [`scene::symbol_of`] the name
    /// (`omega` → `ω`, `mu_k` → `μ_k`, `fk` → `fk`).
    pub fn symbol(&self, name: &str) -> String {
        self.notation.iter().find(|n| n.name == name).map_or_else(|| scene::symbol_of(name), |n| n.symbol.clone())
    }

    /// What parameter `name` is, in a few words (`forcing frequency`): the
    /// scene's `long_name`, else the first line of its `doc`; `None` when
    /// the scene says neither.
    pub fn long_name(&self, name: &str) -> Option<&str> {
        self.notation.iter().find(|n| n.name == name).and_then(|n| n.long_name.as_deref())
    }

    /// What the events at each stop of [`Meta::stops`] are called in figures:
    /// `contacts` at a soft stop, `impacts` at a rigid one.
    pub fn stop_events(&self) -> Vec<&'static str> {
        self.stop_laws.iter().map(|&law| solver::contact::events(law)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meta_names_parameters_by_its_notation_or_the_greek_rule() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/dry-friction.toml");
        let scene = scene::Scene::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
        let notation = Notation::of_scene(&scene);
        assert_eq!(notation.len(), scene.parameter_names().len());
        let plane = crate::Plane::new(
            crate::Axis::parse("omega=0.1:1:3", "x").unwrap(),
            crate::Axis::parse("fk=0:0.3:2", "y").unwrap(),
            crate::Along::X,
        )
        .unwrap();
        let mut meta = Meta {
            scene_name: scene.name().into(),
            scene_toml: scene.source().into(),
            overrides: Vec::new(),
            preset: solver::Preset::Standard,
            accuracy: Vec::new(),
            integrator: solver::Method::Exact,
            plane,
            sweeps: vec![crate::SweepKind::Fresh],
            masses: Vec::new(),
            state_masses: Vec::new(),
            label_stops: Vec::new(),
            stops: Vec::new(),
            stop_normals: Vec::new(),
            stop_laws: Vec::new(),
            dim: 4,
            section_cap: 16,
            notation,
            quantities: Vec::new(),
        };
        assert_eq!(meta.symbol("omega"), "ω");
        assert_eq!(meta.symbol("fk"), "f_k");
        assert_eq!(meta.long_name("omega"), Some("forcing frequency"));
        meta.notation.clear();
        assert_eq!(meta.symbol("omega"), "ω", "no notation (an older file): the Greek rule");
        assert_eq!(meta.symbol("fk"), "fk");
        assert_eq!(meta.long_name("omega"), None);
    }
}
