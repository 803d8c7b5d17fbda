#!/usr/bin/env bash
# Best effort: install Debian's Chromium for the report's browser test (Playwright drives it;
# nothing is downloaded outside the package registries). Without root or apt the test is
# skipped with its reason — except on CI (CI=true), where it must run.
set -u
command -v chromium >/dev/null 2>&1 && exit 0
if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null \
        || echo "install-chromium: apt-get could not install chromium" >&2
else
    echo "install-chromium: not root or no apt-get; the browser test will be skipped" >&2
fi
exit 0
