//! Closed sets of named options (the backend, a scene's string-tagged choices), so that a
//! command line or a message can list them with the names scene files use, without the
//! solver depending on a command-line crate.

/// A value of a closed set, named as in scene files (kebab-case, serde's names).
pub trait Named: Copy + PartialEq + Send + Sync + 'static {
    /// Every value, its name and a one-line help.
    const ALL: &'static [(Self, &'static str, &'static str)];

    /// This value's name.
    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(v, _, _)| *v == self)
            .map(|(_, n, _)| *n)
            .expect("every value is in ALL")
    }

    /// The value of a name, if it is one.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(_, n, _)| *n == name)
            .map(|(v, _, _)| *v)
    }
}

#[cfg(test)]
mod tests {
    use super::Named;
    use crate::backend::BackendChoice;

    /// The names are serde's: a scene file and a command line spell a value alike.
    fn names_are_serde_names<T: Named + serde::Serialize>() {
        for (v, name, help) in T::ALL {
            assert_eq!(serde_json::to_string(v).unwrap(), format!("\"{name}\""));
            assert!(!help.is_empty(), "{name} has no help");
            assert_eq!(T::from_name(name).map(|v| v.name()), Some(*name));
        }
    }

    #[test]
    fn backend_and_scene_choice_names_are_serde_names() {
        use crate::scene::scheme::*;
        names_are_serde_names::<BackendChoice>();
        names_are_serde_names::<IntegratorChoice>();
        names_are_serde_names::<KernelChoice>();
        names_are_serde_names::<DensityForm>();
        names_are_serde_names::<DiffusionForm>();
        names_are_serde_names::<SolidInterface>();
        names_are_serde_names::<ArtStressFrom>();
        names_are_serde_names::<WallCoupling>();
        names_are_serde_names::<NoSlip>();
        names_are_serde_names::<crate::solver::Shown>();
    }
}
