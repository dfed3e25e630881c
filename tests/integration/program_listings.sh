#!/usr/bin/env bash
# mpm_app --list-models prints every registered local model and remote (the registry survives
# the link: mpm_core is an OBJECT library); dem_app --list-backends the backends always built.
# Usage: program_listings.sh MPM_APP DEM_APP
set -uo pipefail
models=$("$1" --list-models) || { echo "FAIL: mpm_app --list-models exited $?"; exit 1; }
backends=$("$2" --list-backends) || { echo "FAIL: dem_app --list-backends exited $?"; exit 1; }
for n in linear_elastic drucker_prager remote; do
  grep -q "^$n " <<<"$models" || { echo "FAIL: mpm_app --list-models lacks $n:"; echo "$models"; exit 1; }
done
for n in elastic native cuda; do
  grep -qx "$n" <<<"$backends" || { echo "FAIL: dem_app --list-backends lacks $n:"; echo "$backends"; exit 1; }
done
echo "ok: $(wc -l <<<"$models") models, $(wc -l <<<"$backends") backends"
