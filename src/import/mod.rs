//! Importers of other programs' rotor files into rotorshunt problem files.
//!
//! Each importer reads a foreign file, maps what rotorshunt can represent, refuses the
//! rest with a typed error naming the element, and renders a problem file in the general
//! form of `problems/README.md`. Importers never write files: the command layer does.

pub mod ross;
