#!/usr/bin/env bash
# check_exports.sh <library> <entry point>: the library's dynamic symbol table
# must define the entry point and nothing else (no leaked OpenVDB/TBB/std/glad
# symbols; the toolchain's _init/_fini are allowed), and it must not link a GL
# library (the host's context is reached through the host's loader).
set -eu
lib=$1
entry=$2
defined=$(nm -D --defined-only "$lib" | awk '{print $NF}' | sed 's/@.*//' | sort -u)
echo "defined dynamic symbols of $lib:"; echo "$defined" | sed 's/^/  /'
unexpected=$(echo "$defined" | grep -vxE "$entry|_init|_fini" || true)
if [ -n "$unexpected" ]; then echo "FAIL: unexpected exported symbols:"; echo "$unexpected"; exit 1; fi
echo "$defined" | grep -qx "$entry" || { echo "FAIL: $entry is not exported"; exit 1; }
if readelf -d "$lib" | grep -Eq 'NEEDED.*(libGL|libEGL|libOpenGL)'; then echo "FAIL: $lib links libGL/libEGL"; exit 1; fi
echo "PASS: $entry alone, no GL library linked"
