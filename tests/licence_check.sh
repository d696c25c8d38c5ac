#!/bin/sh
# Issue 14.5: LICENSE is the BSD 3-Clause licence, and NOTICE.md lists every
# Debian package that scripts/install-deps.sh installs (with its licence).
# Usage: licence_check.sh SOURCE_DIR
set -eu
root=$1
status=0
grep -q "^BSD 3-Clause License" "$root/LICENSE" || { echo "LICENSE is not the BSD 3-Clause licence"; status=1; }
# The package names of install-deps.sh's packages=( ... ) and packages+=( ... ) lists.
packages=$(sed -n '/^packages=(/,/^)/p; /packages+=(/p' "$root/scripts/install-deps.sh" |
  sed 's/#.*//' | tr ' ()' '\n\n\n' | grep -v -e '^packages' -e '^$' -e '^+=$')
[ -n "$packages" ] || { echo "no packages found in scripts/install-deps.sh"; exit 1; }
for p in $packages; do
  # a table row of NOTICE.md naming the package (whole word)
  grep -q -E "^\|.*(^|[^a-z0-9-])$p([^a-z0-9-]|$)" "$root/NOTICE.md" ||
    { echo "NOTICE.md does not list the package $p"; status=1; }
done
exit $status
