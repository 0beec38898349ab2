//! The settings keys of `space-foosball board set KEY VALUE`: `port.N.FIELD`, named
//! after the fields of [`PortSettings`], and their values, checked with
//! [`PortSettings::check`] before anything is sent.

use foosball_protocol::{BoardSettings, PortSettings, PADDLES, SAMPLE_RATES};
use std::fmt;

/// A field of one port's [`PortSettings`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// [`PortSettings::axial_is_y`].
    AxialIsY,
    /// [`PortSettings::invert_axial`].
    InvertAxial,
    /// [`PortSettings::invert_rotation`].
    InvertRotation,
    /// [`PortSettings::resolution_code`].
    ResolutionCode,
    /// [`PortSettings::sample_rate`].
    SampleRate,
}

impl Field {
    /// Every field, in [`PortSettings`] order.
    pub const ALL: [Self; 5] = [
        Self::AxialIsY,
        Self::InvertAxial,
        Self::InvertRotation,
        Self::ResolutionCode,
        Self::SampleRate,
    ];

    /// The field's name in a key (the [`PortSettings`] field's name).
    pub const fn name(self) -> &'static str {
        match self {
            Self::AxialIsY => "axial_is_y",
            Self::InvertAxial => "invert_axial",
            Self::InvertRotation => "invert_rotation",
            Self::ResolutionCode => "resolution_code",
            Self::SampleRate => "sample_rate",
        }
    }

    /// What the field takes, for messages.
    pub fn allowed(self) -> String {
        match self {
            Self::AxialIsY | Self::InvertAxial | Self::InvertRotation => "true or false".to_owned(),
            Self::ResolutionCode => "0 to 3 (1, 2, 4 or 8 counts/mm)".to_owned(),
            Self::SampleRate => {
                let rates: Vec<String> = SAMPLE_RATES.iter().map(u8::to_string).collect();
                format!("one of {} (samples/s)", rates.join(", "))
            }
        }
    }

    fn is_flag(self) -> bool {
        matches!(
            self,
            Self::AxialIsY | Self::InvertAxial | Self::InvertRotation
        )
    }

    /// The field's value in `port`.
    pub fn get(self, port: &PortSettings) -> Value {
        match self {
            Self::AxialIsY => Value::Flag(port.axial_is_y),
            Self::InvertAxial => Value::Flag(port.invert_axial),
            Self::InvertRotation => Value::Flag(port.invert_rotation),
            Self::ResolutionCode => Value::Number(port.resolution_code),
            Self::SampleRate => Value::Number(port.sample_rate),
        }
    }

    /// Sets the field in `port`; a value of the other type changes nothing and says
    /// so.
    fn set(self, port: &mut PortSettings, value: Value) -> bool {
        match (self, value) {
            (Self::AxialIsY, Value::Flag(v)) => port.axial_is_y = v,
            (Self::InvertAxial, Value::Flag(v)) => port.invert_axial = v,
            (Self::InvertRotation, Value::Flag(v)) => port.invert_rotation = v,
            (Self::ResolutionCode, Value::Number(v)) => port.resolution_code = v,
            (Self::SampleRate, Value::Number(v)) => port.sample_rate = v,
            _ => return false,
        }
        true
    }
}

/// A setting's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Value {
    /// An axis flag.
    Flag(bool),
    /// A resolution code or a sample rate.
    Number(u8),
}

impl Value {
    /// The value as JSON.
    pub fn to_json(self) -> serde_json::Value {
        match self {
            Self::Flag(v) => v.into(),
            Self::Number(v) => v.into(),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Flag(v) => write!(f, "{v}"),
            Self::Number(v) => write!(f, "{v}"),
        }
    }
}

/// One setting: a field of one port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    /// The port, 0..8.
    pub port: u8,
    /// The field.
    pub field: Field,
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "port.{}.{}", self.port, self.field.name())
    }
}

/// What a key is made of, for messages.
fn key_help() -> String {
    let fields: Vec<&str> = Field::ALL.iter().map(|f| f.name()).collect();
    format!(
        "keys are port.N.FIELD with N a port 0 to {} and FIELD one of {}",
        PADDLES - 1,
        fields.join(", ")
    )
}

impl std::str::FromStr for Key {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let unknown = || format!("unknown setting {s:?}: {}", key_help());
        let mut parts = s.split('.');
        let (Some("port"), Some(port), Some(field), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return Err(unknown());
        };
        let port = match port.parse::<u8>() {
            Ok(port) if usize::from(port) < PADDLES => port,
            _ => {
                return Err(format!(
                    "no port {port:?} in setting {s:?}: the board's ports are 0 to {}",
                    PADDLES - 1
                ))
            }
        };
        let field = Field::ALL
            .into_iter()
            .find(|f| f.name() == field)
            .ok_or_else(unknown)?;
        Ok(Self { port, field })
    }
}

impl Key {
    /// Parses `text` as this key's value and checks it with [`PortSettings::check`];
    /// the error names the key, the value and what is allowed.
    pub fn parse_value(&self, text: &str) -> Result<Value, String> {
        let bad = || {
            format!(
                "{self}: {text:?} is not allowed; it takes {}",
                self.field.allowed()
            )
        };
        let value = if self.field.is_flag() {
            match text.to_ascii_lowercase().as_str() {
                "true" | "yes" | "on" | "1" => Value::Flag(true),
                "false" | "no" | "off" | "0" => Value::Flag(false),
                _ => return Err(bad()),
            }
        } else {
            Value::Number(text.trim().parse::<u8>().map_err(|_| bad())?)
        };
        // Checked alone, the other fields at their (valid) defaults.
        let mut port = PortSettings::DEFAULT;
        if !self.field.set(&mut port, value) {
            return Err(bad());
        }
        port.check(self.port).map_err(|_| bad())?;
        Ok(value)
    }

    /// The setting's value in `settings`.
    pub fn get(&self, settings: &BoardSettings) -> Value {
        self.field.get(&settings.ports[usize::from(self.port)])
    }

    /// `settings` with this setting at `value` (a value from
    /// [`parse_value`](Self::parse_value)).
    pub fn with(&self, settings: &BoardSettings, value: Value) -> BoardSettings {
        let mut changed = *settings;
        self.field
            .set(&mut changed.ports[usize::from(self.port)], value);
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_name_a_port_and_a_field() {
        let key: Key = "port.3.sample_rate".parse().unwrap();
        assert_eq!(
            key,
            Key {
                port: 3,
                field: Field::SampleRate
            }
        );
        assert_eq!(key.to_string(), "port.3.sample_rate");
        for field in Field::ALL {
            let text = format!("port.7.{}", field.name());
            assert_eq!(text.parse::<Key>().unwrap().to_string(), text);
        }
        for bad in [
            "",
            "port",
            "port.3",
            "port.3.colour",
            "ports.3.sample_rate",
            "port.3.sample_rate.x",
        ] {
            let e = bad.parse::<Key>().unwrap_err();
            assert!(
                e.contains("sample_rate") && e.contains("0 to 7"),
                "{bad}: {e}"
            );
        }
        for bad in [
            "port.8.sample_rate",
            "port.-1.sample_rate",
            "port.x.sample_rate",
        ] {
            let e = bad.parse::<Key>().unwrap_err();
            assert!(e.contains("ports are 0 to 7"), "{bad}: {e}");
        }
    }

    #[test]
    fn values_are_checked_as_the_board_checks_them() {
        let rate: Key = "port.2.sample_rate".parse().unwrap();
        for ok in SAMPLE_RATES {
            assert_eq!(rate.parse_value(&ok.to_string()), Ok(Value::Number(ok)));
        }
        for bad in ["150", "0", "256", "-5", "fast", ""] {
            let e = rate.parse_value(bad).unwrap_err();
            assert!(
                e.starts_with("port.2.sample_rate:") && e.contains("10, 20, 40, 60, 80, 100, 200"),
                "{bad}: {e}"
            );
        }
        let resolution: Key = "port.0.resolution_code".parse().unwrap();
        assert_eq!(resolution.parse_value("0"), Ok(Value::Number(0)));
        let e = resolution.parse_value("4").unwrap_err();
        assert!(e.contains("0 to 3"), "{e}");
        let flag: Key = "port.5.invert_axial".parse().unwrap();
        assert_eq!(flag.parse_value("TRUE"), Ok(Value::Flag(true)));
        assert_eq!(flag.parse_value("0"), Ok(Value::Flag(false)));
        assert!(flag.parse_value("2").unwrap_err().contains("true or false"));
    }

    #[test]
    fn a_setting_changes_only_its_port_and_field() {
        let key: Key = "port.6.invert_rotation".parse().unwrap();
        let before = BoardSettings::DEFAULT;
        let after = key.with(&before, Value::Flag(true));
        assert_eq!(key.get(&after), Value::Flag(true));
        for port in 0..PADDLES {
            let mut expected = before.ports[port];
            if port == 6 {
                expected.invert_rotation = true;
            }
            assert_eq!(after.ports[port], expected, "port {port}");
        }
    }
}
