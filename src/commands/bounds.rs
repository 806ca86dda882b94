//! The commands' side of the parameter rules: a flag's value checked by its rule
//! ([`rotorshunt::analysis::limits`]) and named by the flag. What a run costs is admitted
//! by the run itself ([`rotorshunt::run`]).

use crate::commands::Error;
use rotorshunt::analysis::limits::ParamError;

/// A flag's value by its rule: the value, or the error naming the flag.
pub(crate) fn flag<T>(argument: &str, r: Result<T, ParamError>) -> Result<T, Error> {
    r.map_err(|e| Error::parameter(argument, &e))
}
