#!/bin/sh
# The crate's rustc wrapper (.cargo/config.toml, `build.rustc-workspace-wrapper`): cargo
# runs it as `scripts/rustc-tests.sh <rustc> <args…>` for this crate's own units only, never
# for its dependencies.
#
# A test harness (`--test`: the library's and the binary's unit tests, the integration
# tests) is compiled without optimisation; everything else exactly as cargo asks. What the
# tests spend their time in is the library and the binary, optimised as the profile says;
# the harnesses only call them. `-C opt-level=0` comes last, so it wins over the profile's.
# Measured in docs/decisions.md ("Test harnesses unoptimised").
for arg in "$@"; do
  if [ "$arg" = "--test" ]; then
    exec "$@" -C opt-level=0
  fi
done
exec "$@"
