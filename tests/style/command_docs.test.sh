#!/usr/bin/env bash
# docs/reference/commands/ is every command's --help (scripts/command-docs.sh): fails when a page and the help of
# the binary differ, or a command has no page, or a page no command. Then proves the check can fail: a page with a
# line changed is found.
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"
bash scripts/command-docs.sh "${DEMSA_BINARY:?}" docs --check

copy=$(mktemp -d)
trap 'rm -rf "$copy"' EXIT
cp -r docs "$copy/docs"
sed -i '0,/^Usage:/s//Usage (edited):/' "$copy/docs/reference/commands/run.md"
if bash scripts/command-docs.sh "$DEMSA_BINARY" "$copy/docs" --check >/dev/null 2>&1; then
  echo "an edited page passed the check"
  exit 1
fi
echo "an edited page is found"
