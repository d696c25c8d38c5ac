#!/bin/sh
# A Scilab that plays its Modelica translator (tests/e2e/test_diagram_errors.cpp):
# puts the files of the folder MO_FAKE_TRANSLATION where mocompile's script
# would copy what the translator wrote, then reports success as the script does.
set -e
cp "$MO_FAKE_TRANSLATION"/* "$MO_XCOS_WORK/out/"
echo translated > "$MO_XCOS_WORK/translated"
echo ok > "$MO_XCOS_WORK/status.txt"
echo done > "$MO_XCOS_WORK/done"
