#!/usr/bin/env bash
# The docs a reader follows hold (tests/style/docs_links.py): the commands of README.md, the tutorials and the how-to
# guides exist, the example files they name exist, every relative link of README.md, CONTRIBUTING.md, ARCHITECTURE.md
# and docs/ resolves. Then proves the check can fail: a copy with a broken link, a missing example and an unknown
# command.
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"
python3 tests/style/docs_links.py . "${DEMSA_BINARY:?}"

copy=$(mktemp -d)
trap 'rm -rf "$copy"' EXIT
cp -r README.md CONTRIBUTING.md ARCHITECTURE.md CHANGELOG.md docs examples "$copy/"
printf '\n[gone](docs/gone.md) `demsa frobnicate` examples/gone.toml\n' >>"$copy/README.md"
if out=$(python3 tests/style/docs_links.py "$copy" "$DEMSA_BINARY"); then
  echo "a README with a broken link passed the check"
  exit 1
fi
for expected in "link docs/gone.md" "demsa frobnicate: no such command" "examples/gone.toml: no such file"; do
  [[ $out == *"$expected"* ]] || { echo "the check missed: $expected"; echo "$out"; exit 1; }
done
echo "a broken link, an unknown command and a missing example are found"
