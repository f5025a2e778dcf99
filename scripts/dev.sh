#!/usr/bin/env bash
# Set up dancebots in ./.venv (made from Debian's python3, seeing its system packages) and
#   run the main job:  bash scripts/dev.sh show   (simulates the open-day show into out/)
#   run every test:    bash scripts/dev.sh test
# Works on a fresh Debian 12 as root; installs python3-venv, ffmpeg and espeak-ng with apt-get
# if they are missing, and for the tests Debian's ROS 1 packages (a real roscore for the ROS
# tests), iproute2 (network namespaces), procps and Chromium (show.html in a real browser).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
[ -x "$PY" ] || PY=$(command -v python3)

apt_install() {  # Debian packages the project uses, installed once when missing
  local missing=()
  "$PY" -c 'import ensurepip, venv' 2>/dev/null || missing+=(python3-venv python3-pip)
  command -v ffmpeg >/dev/null || missing+=(ffmpeg)  # MP4 animations of runs
  command -v espeak-ng >/dev/null || missing+=(espeak-ng)  # robots' speech, run --sound
  if [ ${#missing[@]} -gt 0 ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "dancebots: installing ${missing[*]} (apt-get)" >&2
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
      --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

ROS_PACKAGES=(ros-core python3-rospy python3-rosmaster python3-roslaunch python3-tf2-ros
              python3-sensor-msgs python3-geometry-msgs python3-std-msgs)

ros_install() {  # the ROS tests run a real roscore and real nodes
  local missing=()
  command -v roscore >/dev/null && /usr/bin/python3 -c 'import rospy, tf2_ros, roslaunch' \
    2>/dev/null || missing+=("${ROS_PACKAGES[@]}")
  command -v ip >/dev/null || missing+=(iproute2)
  command -v ps >/dev/null || missing+=(procps)
  command -v chromium >/dev/null || missing+=(chromium)  # show.html, tested in a real browser
  if [ ${#missing[@]} -gt 0 ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "dancebots: installing ${missing[*]} (apt-get)" >&2
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
      --no-install-recommends "${missing[@]}" >/dev/null
  fi
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    export DANCEBOTS_REQUIRE_ROS=1  # ROS could be installed: its tests must run, not skip
    export DANCEBOTS_REQUIRE_BROWSER=1  # and Chromium: the replay's test must run too
  fi
}

setup() {
  apt_install
  if [ ! -x .venv/bin/python ]; then
    "$PY" -m venv --system-site-packages .venv
  fi
  local stamp=.venv/.dancebots-installed
  if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
    .venv/bin/python -m pip install -q --disable-pip-version-check -e ".[dev]"
    touch "$stamp"
  fi
}

show() {
  # the main job: simulate the bundled open-day show (thesis listing 6.3) into out/open_day/.
  # `dancebots run` exits 1 when the show ran but not clean (its verdict says why); that is a
  # finding about the show, not a failure of the set-up, so it is reported and this succeeds.
  local status=0
  .venv/bin/dancebots run || status=$?
  if [ "$status" = 1 ]; then
    echo "dancebots: the show ran, but its verdict is NOT CLEAN (see above); outputs in" \
      "out/open_day/" >&2
    return 0
  fi
  return "$status"
}

tests() {
  ros_install
  .venv/bin/ruff check src tests benchmarks
  .venv/bin/mypy
  .venv/bin/python -m pytest
}

setup
case "${1:-show}" in
  show) show ;;
  test) tests ;;
  setup) ;;
  *) echo "usage: bash scripts/dev.sh [show|test|setup]" >&2; exit 2 ;;
esac
