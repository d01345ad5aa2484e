#!/usr/bin/env bash
# expect_command.sh EXIT_CODE REGEX -- COMMAND...
# Runs COMMAND; passes when it exits with EXIT_CODE ("nonzero" accepts any
# failure) and its output (stdout + stderr) matches the extended REGEX.
set -u
want_exit=$1; regex=$2; shift 2
[ "$1" = "--" ] && shift
output=$("$@" 2>&1); got=$?
printf '%s\n' "$output"
if [ "$want_exit" = "nonzero" ]; then
  [ "$got" -ne 0 ] || { echo "expect_command: exit code 0, expected non-zero"; exit 1; }
elif [ "$got" -ne "$want_exit" ]; then
  echo "expect_command: exit code $got, expected $want_exit"; exit 1
fi
printf '%s\n' "$output" | grep -Eq -- "$regex" || { echo "expect_command: output does not match /$regex/"; exit 1; }
echo "expect_command: exit $got and output matches /$regex/"
