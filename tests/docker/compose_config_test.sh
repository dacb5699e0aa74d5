#!/usr/bin/env bash
# Validates docker/compose.yaml and docker/Dockerfile without a Docker engine (none runs here):
#  - `docker-compose config` (Debian's docker-compose, installed by scripts/install-deps) accepts
#    the compose file, which names the server and one agent per robot of config/fleet.yaml, each
#    on the compose network with CYCLONEDDS_URI at config/cyclonedds-compose.xml;
#  - the flags the services pass exist in the binaries' --help texts;
#  - the Dockerfile gets its Debian packages through scripts/install-deps only and copies every
#    file it names from the repository.
# Usage: compose_config_test.sh SOURCE_DIR. Exit 0 when all holds, 1 with the reasons otherwise.
set -uo pipefail

src="${1:?usage: $0 SOURCE_DIR}"
cd "$src" || exit 1
compose=docker/compose.yaml
dockerfile=docker/Dockerfile
uri_in_image=file:///opt/fleet/config/cyclonedds-compose.xml

failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# ---- docker-compose config --------------------------------------------------------------------
if ! command -v docker-compose >/dev/null 2>&1; then
  echo "FAIL: docker-compose is not installed (scripts/install-deps installs Debian's docker-compose)" >&2
  exit 1
fi
# The defaults of the file, not whatever the calling shell exports.
unset FLEET_SITE FLEET_TIME_SCALE FLEET_API_TOKEN COMPOSE_FILE COMPOSE_PROJECT_NAME
if ! config="$(docker-compose -f "$compose" config 2>&1)"; then
  echo "$config" >&2
  echo "FAIL: docker-compose -f $compose config refuses the file" >&2
  exit 1
fi
services="$(docker-compose -f "$compose" config --services 2>/dev/null | sort | tr '\n' ' ' | sed 's/ $//')"

# The lines of one service in the normalised output (keys at two spaces under services:).
service_block() {
  awk -v want="  $1:" '
    /^services:/ { inside = 1; next }
    inside && /^[^ ]/ { inside = 0 }
    inside && /^  [^ ]/ { current = $0 }
    inside && current == want { print }' <<<"$config"
}
# The list items of KEY (command, ports, healthcheck test, ...) in a service block, one per
# line, unquoted.
block_list() {
  awk -v key="$2:" '
    indent == "" && $1 == key && NF == 1 { indent = substr($0, 1, index($0, key) - 1); next }
    indent != "" && index($0, indent "- ") == 1 {
      item = substr($0, length(indent) + 3); gsub(/^'\''|'\''$/, "", item); print item; next }
    indent != "" { exit }' <<<"$(service_block "$1")"
}

# The server and four agents, each agent one of the robots config/fleet.yaml declares (it
# declares more, for larger soak runs; the compose file runs the first four).
declared="$(sed -n 's/^ *- *{ *id: *\([A-Za-z0-9_-]*\).*/\1/p' config/fleet.yaml)"
[ -n "$declared" ] || fail "no robots found in config/fleet.yaml"
robots="$(head -n 4 <<<"$declared" | sort)"
# shellcheck disable=SC2086  # one word per robot
expected="$(printf '%s\n' $robots server | sort | tr '\n' ' ' | sed 's/ $//')"
[ "$services" = "$expected" ] || fail "services are '$services', expected '$expected' (server + the first four robots of config/fleet.yaml)"

# The network.
awk '/^networks:/ { inside = 1; next } inside && /^[^ ]/ { inside = 0 } inside' <<<"$config" |
  grep -q '^  fleet:' || fail "no top-level network 'fleet'"
awk '/^networks:/ { inside = 1; next } inside && /^[^ ]/ { inside = 0 } inside' <<<"$config" |
  grep -q '^    driver: bridge$' || fail "network 'fleet' is not a bridge"

# DIR FLAG: the flag is in the --help text of the binary built from DIR (a line "  --flag ...").
flag_documented() {
  grep -qE -- "^ +$2( |\$)" "$1"/*.cpp
}

for service in server $robots; do
  block="$(service_block "$service")"
  [ -n "$block" ] || { fail "service '$service' missing"; continue; }
  grep -qx "      CYCLONEDDS_URI: $uri_in_image" <<<"$block" ||
    fail "$service: CYCLONEDDS_URI is not $uri_in_image"
  grep -A1 -x '    networks:' <<<"$block" | grep -qx '      fleet: null' ||
    fail "$service: not on the network 'fleet'"
  grep -qx '      dockerfile: docker/Dockerfile' <<<"$block" ||
    fail "$service: not built from docker/Dockerfile"

  command_words="$(block_list "$service" command)"
  binary="$(head -n1 <<<"$command_words")"
  case "$binary" in
    fleet-server) main=server ;;
    fleet-agent) main=agent ;;
    *) fail "$service: command runs '$binary', not fleet-server or fleet-agent"; continue ;;
  esac
  # shellcheck disable=SC2013  # flags are single words
  for flag in $(grep '^--' <<<"$command_words"); do
    flag_documented "$main" "$flag" || fail "$service: $binary has no flag $flag (not in the --help text in $main/)"
  done

  if [ "$service" = server ]; then
    grep -A1 -x -- '--http-host' <<<"$command_words" | grep -qx '0.0.0.0' ||
      fail "server: the web view must bind 0.0.0.0 inside the container (--http-host 0.0.0.0)"
    [ "$(block_list server ports)" = "127.0.0.1:8080:8080/tcp" ] ||
      fail "server: ports are '$(block_list server ports)', expected only 127.0.0.1:8080:8080"
    grep -q 'fleetctl' <<<"$(block_list server test)" || fail "server: no fleetctl healthcheck"
    for flag in $(block_list server test | grep -o -- ' --[a-z-]*'); do
      flag_documented cli "$flag" || fail "server: healthcheck's fleetctl has no flag $flag (not in the --help text in cli/)"
    done
  else
    [ "$binary" = fleet-agent ] || fail "$service: runs $binary, expected fleet-agent"
    grep -A1 -x -- '--id' <<<"$command_words" | grep -qx "$service" ||
      fail "$service: fleet-agent does not run with --id $service"
    grep -A1 -x '    depends_on:' <<<"$block" | grep -qx '      server:' ||
      fail "$service: does not depend on the server"
  fi
done

# ---- docker/compose.security.yaml over it: a security folder in every container, HTTPS ---------
security_compose=docker/compose.security.yaml
if ! config="$(FLEET_SECURITY_DIR=/srv/fleet-security docker-compose -f "$compose" -f "$security_compose" config 2>&1)"; then
  echo "$config" >&2
  fail "docker-compose refuses $compose with $security_compose"
else
  for service in server $robots; do
    block="$(service_block "$service")"
    grep -qx "      FLEET_SECURITY: /opt/fleet/security" <<<"$block" ||
      fail "$service: $security_compose sets no FLEET_SECURITY=/opt/fleet/security"
    grep -qx "      CYCLONEDDS_URI: $uri_in_image" <<<"$block" || fail "$service: $security_compose drops CYCLONEDDS_URI"
    block_list "$service" volumes | grep -qx "/srv/fleet-security:/opt/fleet/security:ro" ||
      fail "$service: $security_compose does not mount the folder read-only at /opt/fleet/security"
    main=agent
    [ "$service" = server ] && main=server
    for flag in $(block_list "$service" command | grep '^--'); do
      flag_documented "$main" "$flag" || fail "$service: no flag $flag in $main/ (with $security_compose)"
    done
  done
  block_list server command | grep -qx -- "--http-tls-cert" || fail "server: $security_compose serves no HTTPS"
fi
if unset FLEET_SECURITY_DIR && docker-compose -f "$compose" -f "$security_compose" config >/dev/null 2>&1; then
  fail "$security_compose is taken without FLEET_SECURITY_DIR"
fi

# ---- the Cyclone configuration the containers use ---------------------------------------------
xml="config/${uri_in_image##*/config/}"
if [ ! -f "$xml" ]; then
  fail "$xml (CYCLONEDDS_URI in the image) does not exist"
else
  if command -v xmllint >/dev/null 2>&1; then
    xmllint --noout "$xml" || fail "$xml is not well-formed XML"
  else
    python3 -c 'import sys, xml.etree.ElementTree as e; e.parse(sys.argv[1])' "$xml" ||
      fail "$xml is not well-formed XML"
  fi
  grep -q '<NetworkInterface name="eth0" multicast="true"/>' "$xml" ||
    fail "$xml does not use the container's eth0 with multicast"
  lease="$(grep -o '<LeaseDuration>[^<]*</LeaseDuration>' config/cyclonedds.xml)"
  grep -qF "$lease" "$xml" || fail "$xml: lease differs from config/cyclonedds.xml ($lease)"
fi

# ---- the Dockerfile ---------------------------------------------------------------------------
# Instructions with their continuation lines joined, comments dropped.
instructions="$(sed -e '/^[[:space:]]*#/d' -e ':a' -e '/\\$/{N;s/\\\n/ /;ba' -e '}' "$dockerfile")"

# Every base image is Debian 12.
while read -r _ image _; do
  case "$image" in
    debian:bookworm) ;;
    *) grep -qiE "^FROM .* AS $image\$" <<<"$instructions" || fail "Dockerfile: base image '$image' is not debian:bookworm" ;;
  esac
done < <(grep -iE '^FROM ' <<<"$instructions")

# Packages come from scripts/install-deps, run with flags it accepts.
deps_run="$(grep -E '^RUN .*install-deps' <<<"$instructions" | head -n1)"
if [ -z "$deps_run" ]; then
  fail "Dockerfile does not run scripts/install-deps"
  allowed=""
else
  deps_flags="$(sed -E 's/.*install-deps((\s+--[a-z-]+)*).*/\1/' <<<"$deps_run")"
  # shellcheck disable=SC2086
  if ! allowed="$(scripts/install-deps --list $deps_flags)"; then
    fail "Dockerfile runs install-deps with flags it does not accept:$deps_flags"
  fi
  if grep -q -- '--build-only' <<<"$deps_flags"; then
    # The build-only list has no test or benchmark libraries: the image must not build them.
    for option in -DFLEET_BUILD_TESTS=OFF -DFLEET_BUILD_BENCH=OFF; do
      grep -qF -- "$option" <<<"$instructions" || fail "Dockerfile: install-deps --build-only but no $option"
    done
  fi
fi
# Any package the Dockerfile names to apt-get itself must be one of install-deps'.
while read -r install; do
  for word in ${install#apt-get install}; do
    case "$word" in -*|*'$'*|*'"'*|*"'"*) continue ;; esac
    grep -qx -- "$word" <<<"$allowed" || fail "Dockerfile installs '$word', which scripts/install-deps does not list"
  done
done < <(grep -oE 'apt-get install[^;&|]*' <<<"$instructions")
# No other way for software to come in.
grep -E '^RUN ' <<<"$instructions" | grep -qwE 'pip3?|npm|curl|wget|git clone|add-apt-repository' &&
  fail "Dockerfile fetches software outside scripts/install-deps: $(grep -E '^RUN ' <<<"$instructions" | grep -wE 'pip3?|npm|curl|wget|git clone|add-apt-repository' | head -n1)"

# Every COPY from the build context exists and is not left out of the context by .dockerignore.
copied=""
while read -r line; do
  grep -q -- '--from=' <<<"$line" && continue
  read -r -a parts <<<"$line"
  for ((i = 1; i < ${#parts[@]} - 1; i++)); do
    path="${parts[$i]%/}"
    copied+="$path "
    [ -e "$path" ] || fail "Dockerfile copies '$path', which is not in the repository"
    [ -f .dockerignore ] && grep -qxF "${path%%/*}" .dockerignore &&
      fail "Dockerfile copies '$path', but .dockerignore leaves it out"
  done
done < <(grep -E '^COPY ' <<<"$instructions")
# The sources the build needs: the folders CMakeLists.txt adds (but the benchmarks), core/, cmake/.
for dir in cmake core $(sed -n 's/^ *add_subdirectory(\([a-z0-9_]*\))$/\1/p' CMakeLists.txt | grep -vx bench); do
  grep -qw -- "$dir" <<<"$copied" || fail "Dockerfile does not copy $dir/, which the build needs"
done
# The runtime stage: the binaries the services run, maps/ and config/ under FLEET_HOME.
for binary in fleet-server fleet-agent fleetctl; do
  grep -E '^COPY --from=' <<<"$instructions" | grep -q "/$binary" || fail "Dockerfile: the image lacks $binary"
done
grep -qE '^COPY config/? /opt/fleet/config/?$' <<<"$instructions" || fail "Dockerfile: config/ is not at /opt/fleet/config"
grep -qE '^COPY maps/? /opt/fleet/maps/?$' <<<"$instructions" || fail "Dockerfile: maps/ is not at /opt/fleet/maps"
grep -qE '^ENV FLEET_HOME=/opt/fleet$' <<<"$instructions" || fail "Dockerfile: FLEET_HOME is not /opt/fleet"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "docker/compose.yaml and docker/Dockerfile: services $services; all checks passed"
