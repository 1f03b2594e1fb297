//! One spelling for every choice a user names: each enum below `named_enum!` lists its variants
//! with their names once, and everything else derives from that list (`ALL`, `name`,
//! `from_name`, `FromStr`, `Display`, serde as the name, the WGSL constants of the kernel's
//! `override`s, the command line's possible values).

/// A choice with a fixed set of named values.
pub trait Named: Copy + PartialEq + 'static {
    /// Every value, in declaration order.
    fn all() -> &'static [Self];
    /// The spelling on the command line, in files and headers.
    fn name(self) -> &'static str;
    /// One line saying what it is (the variant's doc comment).
    fn description(self) -> &'static str;
    /// The value called `name`, if any.
    fn from_name(name: &str) -> Option<Self> {
        Self::all().iter().copied().find(|v| v.name() == name)
    }
    /// Every name, in declaration order.
    fn names() -> Vec<&'static str> {
        Self::all().iter().map(|v| v.name()).collect()
    }
}

/// A name that is not one of a `Named` type's.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("unknown {what} `{name}` (known: {known})")]
pub struct UnknownName {
    pub what: &'static str,
    pub name: String,
    pub known: String,
}

impl UnknownName {
    pub fn of<T: Named>(what: &'static str, name: &str) -> UnknownName {
        UnknownName { what, name: name.to_string(), known: T::names().join(", ") }
    }
}

/// Looks `name` up, or says which names there are.
pub fn parse_name<T: Named>(what: &'static str, name: &str) -> Result<T, UnknownName> {
    T::from_name(name).ok_or_else(|| UnknownName::of::<T>(what, name))
}

/// The WGSL constants naming the values of `T` (`PREFIX_NAME: u32 = index`, the name upper-cased
/// with `-` as `_`): the kernel compares its `override` against these, the host passes `index`.
pub fn wgsl_constants<T: Named>(prefix: &str) -> String {
    T::all()
        .iter()
        .enumerate()
        .map(|(i, v)| format!("const {prefix}_{}: u32 = {i}u;\n", v.name().to_uppercase().replace('-', "_")))
        .collect()
}

/// Declares a `Named` enum: `named_enum! { /// doc \n pub enum E("what") { /// doc \n A = "a", ... } }`.
/// Variants are numbered from 0 in order (the value a WGSL `override` gets).
macro_rules! named_enum {
    (
        $(#[doc = $doc:expr])*
        $vis:vis enum $name:ident($what:literal) {
            $( $(#[doc = $vdoc:expr])* $variant:ident = $text:literal ),+ $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        $vis enum $name {
            $( $(#[doc = $vdoc])* $variant ),+
        }

        impl $name {
            /// Every value, in declaration order.
            pub const ALL: [$name; [$($text),+].len()] = [$($name::$variant),+];

            /// The spelling on the command line, in files and headers.
            pub const fn name(self) -> &'static str {
                match self { $($name::$variant => $text),+ }
            }

            /// Value of the WGSL constant this choice sets (its position in `ALL`).
            pub const fn constant(self) -> u32 {
                self as u32
            }
        }

        impl $crate::names::Named for $name {
            fn all() -> &'static [Self] {
                &Self::ALL
            }
            fn name(self) -> &'static str {
                $name::name(self)
            }
            fn description(self) -> &'static str {
                match self { $($name::$variant => concat!($($vdoc, " "),*)),+ }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl std::str::FromStr for $name {
            type Err = $crate::names::UnknownName;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                $crate::names::parse_name($what, s)
            }
        }

        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        impl<'de> serde::Deserialize<'de> for $name {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = <String as serde::Deserialize>::deserialize(d)?;
                s.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}

pub(crate) use named_enum;
