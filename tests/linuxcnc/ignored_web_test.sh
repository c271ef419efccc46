#!/bin/bash
# linuxcnc.ignored_web: a run configuration with [web] given to trueaxis-hal (which serves no page)
# is not silently ignored: the component says so at start, naming the file, the line and the key.
#   ignored_web_test.sh TRUEAXIS_HAL EXAMPLE_CONFIG
set -euo pipefail
hal=$1 example=$2
tmp=$(mktemp -d /tmp/trueaxis-ignored-web.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
# The example, on loopback (no terminal listens on port 1), with a model that does not exist: the
# component stops at the model after its start-up messages.
sed -e 's/^host = .*/host = "127.0.0.1"/' -e 's/^port = 502/port = 1/' -e "s|^file = .*|file = \"$tmp/absent.json\"|" \
  "$example" >"$tmp/run.toml"
printf '\n[web]\nlisten = "127.0.0.1:8080"\n' >>"$tmp/run.toml"
line=$(grep -n '^listen' "$tmp/run.toml" | cut -d: -f1)
set +e
timeout 60 "$hal" --config "$tmp/run.toml" >"$tmp/out" 2>&1
rc=$?
set -e
[[ $rc != 0 && $rc != 124 ]] || { cat "$tmp/out"; echo "FAIL: exit $rc (expected a refusal of the absent model)"; exit 1; }
grep -qF "$tmp/run.toml:$line: [web] listen = \"127.0.0.1:8080\" is ignored" "$tmp/out" \
  || { cat "$tmp/out"; echo "FAIL: no warning naming $tmp/run.toml:$line and [web] listen"; exit 1; }
grep -q "absent.json" "$tmp/out" || { cat "$tmp/out"; echo "FAIL: the absent model was not named"; exit 1; }
echo "PASS [the ignored [web] is named at $tmp/run.toml:$line]"
