#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs crossparam into a temporary prefix and builds a consumer project with find_package(crossparam).
set -eu
build=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$src/test/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer"
echo "install: 1 passed, 0 failed"
