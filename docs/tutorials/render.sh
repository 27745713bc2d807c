#!/usr/bin/env bash
# Executes every numbered tutorial and writes its rendered copy (Markdown + figures) to
# docs/tutorials/rendered/. Usage: bash docs/tutorials/render.sh [BUILD_DIR]  (default build)
# The notebooks themselves are committed without outputs.
set -euo pipefail
cd "$(dirname "$0")"
build=$(cd "../../${1:-build}" && pwd)
unset MPLBACKEND  # the kernel's inline backend, so that the figures are kept
export PYTHONPATH="$build/python" PPOHDEM_SOURCE_DIR="$(cd ../.. && pwd)" \
       JUPYTER_PATH="$build/jupyter" PPOHDEM_EXE="$build/apps/ppohdem"
rm -rf rendered
mkdir -p rendered
for notebook in [0-9][0-9]-*.ipynb; do
  /usr/bin/python3 -m nbconvert --execute --to markdown --ExecutePreprocessor.kernel_name=python3 \
    --ExecutePreprocessor.timeout=300 --output-dir rendered "$notebook"
done
# Temporary paths and run headers differ from run to run: keep the copies readable, not noisy.
sed -i -E 's#/tmp/tmp[a-z0-9_]+#/tmp/...#g' rendered/*.md
