#!/usr/bin/env bash
# Installs Fleet into a temporary prefix and runs `fleetctl demo` from there with the source and
# build trees hidden (a private mount namespace lays an empty tmpfs over them), so the installed
# binaries must find config/ and maps/ under PREFIX/share/fleet on their own. Then packages the
# build with `cpack -G DEB` and checks the package's dependencies, files and maintainer scripts.
#   install_test.sh SOURCE_DIR BUILD_DIR DOMAIN
# Exit 0 when all holds, 1 with the reason otherwise, 77 (skipped) when no mount namespace can
# be made here.
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
domain=$3
work=$(mktemp -d /tmp/fleet-install-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "install_test: $*" >&2; exit 1; }

prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; fail "cmake --install failed"; }
for f in bin/fleet-server bin/fleet-agent bin/fleetctl bin/fleet-vda5050 share/fleet/config/fleet.yaml \
         share/fleet/config/cyclonedds.xml share/fleet/maps/table_a.yaml share/fleet/maps/table_a.xodr \
         lib/systemd/system/fleet-server.service; do
  [ -e "$prefix/$f" ] || fail "cmake --install left out $f"
done
grep -qx "ExecStart=$prefix/bin/fleet-server" "$prefix/lib/systemd/system/fleet-server.service" ||
  fail "the unit does not start $prefix/bin/fleet-server"

# The demo, with the trees it was built from out of reach.
hide="mount -t tmpfs fleet-hidden '$src'"
case "$build/" in "$src"/*) ;; *) hide="$hide && mount -t tmpfs fleet-hidden '$build'" ;; esac
run="$hide && [ ! -e '$src/config/fleet.yaml' ] && cd / && XDG_STATE_HOME='$work/state' HOME='$work' \
  '$prefix/bin/fleetctl' --domain $domain demo --agents 2 --duration 20 --time-scale 10 --http-port 0 --json"
if [ "$(id -u)" -eq 0 ]; then ns=(unshare --mount); else ns=(unshare --map-root-user --mount); fi
if ! "${ns[@]}" true 2>/dev/null; then
  echo "install_test: skipped: no private mount namespace here (${ns[*]} failed)" >&2
  exit 77
fi
set +e
"${ns[@]}" bash -c "$run" >"$work/demo.out" 2>"$work/demo.err"
status=$?
set -e
summary=$(tail -n 1 "$work/demo.out")
[ $status -eq 0 ] || { cat "$work/demo.err" >&2; fail "the installed demo exited $status: $summary"; }
echo "installed demo: $summary"
done_count=$(sed -n 's/.*"orders_done":\([0-9]*\).*/\1/p' <<<"$summary")
collisions=$(sed -n 's/.*"collisions":\([0-9]*\).*/\1/p' <<<"$summary")
[ -n "$done_count" ] && [ "$done_count" -ge 1 ] || fail "the installed demo finished no order: $summary"
[ "$collisions" = 0 ] || fail "the installed demo reports collisions: $summary"
ls -d "$work"/state/fleet/runs/demo-* >/dev/null 2>&1 ||
  fail "the demo's run folder is not under \$XDG_STATE_HOME/fleet/runs"

# The Debian package.
(cd "$build" && cpack -G DEB -B "$work/deb" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
deb=$(ls "$work"/deb/*.deb)
depends=$(dpkg-deb --field "$deb" Depends)
echo "package $(basename "$deb"): Depends: $depends"
for lib in libddsc0debian libompl libspdlog libyaml-cpp libsqlite3 libpaho-mqttpp passwd; do
  grep -q "$lib" <<<"$depends" || fail "Depends does not name $lib: $depends"
done
contents=$(dpkg-deb --contents "$deb")
for f in ./usr/bin/fleet-server ./usr/bin/fleetctl ./usr/bin/fleet-vda5050 ./usr/share/fleet/config/fleet.yaml \
         ./usr/share/fleet/maps/warehouse.xodr ./usr/lib/systemd/system/fleet-server.service; do
  grep -q " $f\$" <<<"$contents" || fail "the package holds no $f"
done
# Read whole before grep: with pipefail, grep -q leaving early fails the pipe on tar's SIGPIPE.
control=$(dpkg-deb --ctrl-tarfile "$deb" | tar -t)
grep -q '^./postinst$' <<<"$control" || fail "the package has no postinst: $control"
unit=$(dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/lib/systemd/system/fleet-server.service)
grep -qx 'ExecStart=/usr/bin/fleet-server' <<<"$unit" || fail "the packaged unit does not start /usr/bin/fleet-server"
echo "install_test: ok"
