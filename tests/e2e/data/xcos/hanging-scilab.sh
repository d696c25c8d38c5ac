#!/bin/sh
# A Scilab that hangs (tests/e2e/test_diagram_errors.cpp: the time limit).
exec sleep 60
