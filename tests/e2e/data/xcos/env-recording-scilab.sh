#!/bin/sh
# A Scilab that writes the _JAVA_OPTIONS and TMPDIR it was given to the file
# MO_TEST_RECORD, then stops (tests/e2e/test_diagram_errors.cpp).
printf '%s\n%s\n' "$_JAVA_OPTIONS" "$TMPDIR" > "$MO_TEST_RECORD"
