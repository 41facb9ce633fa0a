//! [`SettingsPatch`]: some physics settings given values of their own,
//! laid over other settings — a `Set` event's live settings, a benchmark
//! run's `settings`.

use serde::de::{Deserializer, Error, MapAccess};
use serde::ser::{SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

use super::settings::SimulationSettings;
use super::settings_by_name::{setting, unknown_setting};
use crate::input::{ReadByHand, deserialize_by_hand};

/// Physics settings given values of their own; the others are left as
/// they are where the patch is applied. Written as the settings a scenario
/// file writes, by their names: `(seed: 5, shatter_threshold: 2.0)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SettingsPatch {
    /// The values: the defaults with those of `keys` changed.
    pub values: SimulationSettings,
    /// The settings given, in file order.
    pub keys: Vec<&'static str>,
}

impl SettingsPatch {
    /// The patch of the settings `keys` (names in files) whose values
    /// `values` holds; names that are no setting's are left out.
    pub fn of(values: &SimulationSettings, keys: impl IntoIterator<Item = &'static str>) -> Self {
        Self {
            values: values.clone(),
            keys: keys.into_iter().filter(|key| setting(key).is_some()).collect(),
        }
    }

    /// Whether it gives no setting.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Lays its values over `settings`.
    pub fn apply(&self, settings: &mut SimulationSettings) {
        for key in &self.keys {
            settings.take(key, &self.values);
        }
    }

    /// Reads the value of the setting named `key` from `map`, checked by
    /// its rule; `Ok(false)` where no setting has that name (the value is
    /// then not read), an error where the patch gives it already.
    pub fn read_field<'de, A: MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<bool, A::Error> {
        let Some(info) = setting(key) else {
            return Ok(false);
        };
        if self.keys.contains(&info.key) {
            return Err(A::Error::custom(format!("duplicate field `{key}`")));
        }
        self.values.read_field(info.key, map)?;
        self.keys.push(info.key);
        Ok(true)
    }

    /// Writes each setting it gives, by its name, into `out`.
    pub fn serialize_fields<S: SerializeStruct>(&self, out: &mut S) -> Result<(), S::Error> {
        /// One setting's value, written as the settings write it.
        struct Value<'a>(&'a SimulationSettings, &'static str);
        impl Serialize for Value<'_> {
            fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
                self.0.serialize_value(self.1, out)
            }
        }
        for key in &self.keys {
            out.serialize_field(key, &Value(&self.values, key))?;
        }
        Ok(())
    }
}

impl ReadByHand for SettingsPatch {
    const NAME: &'static str = "Settings";
    const FIELDS: &'static [&'static str] = &[];
    const EXPECTING: &'static str = "physics settings by their names, as (seed: 5, shatter_threshold: 2.0)";

    fn read<'de, A: MapAccess<'de>>(mut map: A) -> Result<Self, A::Error> {
        let mut patch = SettingsPatch::default();
        while let Some(crate::input::FieldName(key)) = map.next_key()? {
            if !patch.read_field(&key, &mut map)? {
                return Err(unknown_setting(&key, &[]));
            }
        }
        Ok(patch)
    }
}

impl<'de> Deserialize<'de> for SettingsPatch {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

impl Serialize for SettingsPatch {
    fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
        let mut s = out.serialize_struct("Settings", self.keys.len())?;
        self.serialize_fields(&mut s)?;
        s.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_changes_what_it_gives_and_keeps_the_rest() {
        let patch: SettingsPatch = ron::from_str("(seed: 5, shatter_threshold: 2.5)").unwrap();
        assert_eq!(patch.keys, ["seed", "shatter_threshold"]);
        let mut settings = SimulationSettings {
            time_step: 0.5,
            ..SimulationSettings::DEFAULT
        };
        patch.apply(&mut settings);
        assert_eq!((settings.seed, settings.shatter_threshold), (5, 2.5));
        assert_eq!(settings.time_step, 0.5, "kept");
        let written = ron::to_string(&patch).unwrap();
        assert_eq!(ron::from_str::<SettingsPatch>(&written).unwrap(), patch, "{written}");
    }

    #[test]
    fn a_patch_holds_its_values_to_their_rules() {
        for (text, needle) in [
            (
                "(shatter_fragments: 1)",
                "field `shatter_fragments`: must be between 2 and 1000, got 1",
            ),
            ("(seed: 1, seed: 2)", "duplicate field `seed`"),
            (
                "(threshold: 1)",
                "unknown field `threshold`, expected one of `gravitational_constant`",
            ),
        ] {
            let e = ron::from_str::<SettingsPatch>(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
    }
}
