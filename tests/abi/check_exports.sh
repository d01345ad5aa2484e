#!/usr/bin/env bash
# The plugin's dynamic symbol table must define atmo_negotiate and nothing
# else (no leaked OpenVDB/TBB/std/glad symbols); the toolchain's _init/_fini
# are allowed.
set -eu
lib=$1
defined=$(nm -D --defined-only "$lib" | awk '{print $NF}' | sed 's/@.*//' | sort -u)
echo "defined dynamic symbols of $lib:"; echo "$defined" | sed 's/^/  /'
unexpected=$(echo "$defined" | grep -vxE 'atmo_negotiate|_init|_fini' || true)
if [ -n "$unexpected" ]; then echo "FAIL: unexpected exported symbols:"; echo "$unexpected"; exit 1; fi
echo "$defined" | grep -qx atmo_negotiate || { echo "FAIL: atmo_negotiate is not exported"; exit 1; }
if readelf -d "$lib" | grep -Eq 'NEEDED.*(libGL|libEGL|libOpenGL)'; then echo "FAIL: the plugin links libGL/libEGL"; exit 1; fi
echo "PASS: atmo_negotiate alone, no GL library linked"
