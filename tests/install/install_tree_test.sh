#!/bin/bash
# install.tree (tests/install/CMakeLists.txt): `cmake --install` into a temporary prefix, then the
# installed program run from there — its version, the shipped configuration and systemd units, the
# web front end serving the installed pages on 127.0.0.1, the installed tree moved elsewhere, and a
# binary copied alone (which must say where it looked for its pages).
#   install_tree_test.sh CMAKE BUILD_DIR SOURCE_DIR VERSION HAVE_HAL(ON|OFF)
set -euo pipefail
cmake=$1 build=$2 source=$3 version=$4 have_hal=$5

tmp=$(mktemp -d /tmp/trueaxis-install-tree.XXXXXX)  # outside the build tree on purpose
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

prefix=$tmp/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }

# --- what lands where ---
for f in bin/trueaxis share/trueaxis/web/login.html share/trueaxis/examples/machines/vmc850.toml \
         share/trueaxis/examples/terminal/w1_devices/28-0316a2794aff/w1_slave \
         share/doc/trueaxis/README.md share/doc/trueaxis/docs/install.md share/doc/trueaxis/docs/web.md \
         etc/trueaxis/shop.toml etc/trueaxis/terminal.toml etc/trueaxis/server.env etc/trueaxis/web.env; do
  [[ -f $prefix/$f ]] || fail "not installed: $f"
done
[[ -x $prefix/bin/trueaxis ]] || fail "bin/trueaxis is not executable"
if [[ $have_hal == ON ]]; then
  for f in bin/trueaxis-hal bin/trueaxis-hal-plant; do [[ -x $prefix/$f ]] || fail "not installed: $f"; done
fi
diff <(cd "$source/src/web/static" && ls) <(cd "$prefix/share/trueaxis/web" && ls) || fail "the web pages differ from src/web/static"

# --- the systemd units name this prefix's program and configuration ---
for name in server terminal web; do
  unit=$prefix/lib/systemd/system/trueaxis-$name.service
  [[ -f $unit ]] || fail "not installed: lib/systemd/system/trueaxis-$name.service"
  ! grep -n '@[A-Z_]*@' "$unit" || fail "$unit: a placeholder was not replaced"
  exec_start=$(sed -n 's/^ExecStart=//p' "$unit")
  [[ $exec_start == "$prefix/bin/trueaxis $name "* ]] || fail "$unit: ExecStart=$exec_start does not run $prefix/bin/trueaxis $name"
  grep -qx 'User=trueaxis' "$unit" || fail "$unit: not run as the trueaxis user"
  grep -qx 'StateDirectory=trueaxis' "$unit" || fail "$unit: no StateDirectory"
  grep -qx 'ProtectSystem=strict' "$unit" || fail "$unit: no ProtectSystem=strict"
  grep -qx 'Restart=on-failure' "$unit" || fail "$unit: no Restart=on-failure"
done
grep -q -- "--config $prefix/etc/trueaxis/shop.toml" "$prefix/lib/systemd/system/trueaxis-server.service" || fail "the server unit does not read etc/trueaxis/shop.toml"
grep -q -- "--config $prefix/etc/trueaxis/terminal.toml" "$prefix/lib/systemd/system/trueaxis-terminal.service" || fail "the terminal unit does not read etc/trueaxis/terminal.toml"
grep -qx 'AmbientCapabilities=CAP_NET_BIND_SERVICE' "$prefix/lib/systemd/system/trueaxis-terminal.service" || fail "the terminal cannot bind port 502"
if command -v systemd-analyze >/dev/null; then
  # The user trueaxis exists only where the package is installed: its absence is the one finding allowed.
  for name in server terminal web; do
    if ! systemd-analyze verify "$prefix/lib/systemd/system/trueaxis-$name.service" >"$tmp/verify.log" 2>&1; then
      if grep -v -i "user.*trueaxis\|trueaxis.*user" "$tmp/verify.log" | grep -q .; then cat "$tmp/verify.log"; fail "systemd-analyze verify trueaxis-$name.service"; fi
    fi
  done
fi

# --- the version is the project's ---
[[ $("$prefix/bin/trueaxis" --version) == "trueaxis $version" ]] || fail "--version: $("$prefix/bin/trueaxis" --version)"

# --- installing again keeps the shop's edited configuration ---
echo '# edited by the shop' >>"$prefix/etc/trueaxis/shop.toml"
"$cmake" --install "$build" --prefix "$prefix" >"$tmp/install2.log" || { cat "$tmp/install2.log"; fail "second cmake --install"; }
grep -qx '# edited by the shop' "$prefix/etc/trueaxis/shop.toml" || fail "a second install overwrote etc/trueaxis/shop.toml"

# --- the installed tree, moved elsewhere, still finds its pages and examples ---
moved=$tmp/elsewhere/opt-trueaxis
mkdir -p "$tmp/elsewhere"
mv "$prefix" "$moved"
bin=$moved/bin/trueaxis
cd "$tmp"  # no examples/ here
printf 'correct horse battery\n' >"$tmp/password"
"$bin" user add --users "$tmp/users.db" --name chief --role admin --password-file "$tmp/password" >/dev/null
marker="<!-- served from the installed pages $$ -->"
echo "$marker" >>"$moved/share/trueaxis/web/login.html"
: >"$tmp/web.err"  # exists before the background program opens it: the loop below reads it at once
"$bin" web --listen 127.0.0.1:0 --users "$tmp/users.db" --machines 2 --duration-s 300 >"$tmp/web.out" 2>"$tmp/web.err" &
web_pid=$!
pids+=("$web_pid")
url=""
while [[ -z $url ]]; do
  kill -0 "$web_pid" 2>/dev/null || { cat "$tmp/web.err"; fail "trueaxis web (installed, moved) did not start"; }
  url=$(sed -n 's|^web: \(http://127\.0\.0\.1:[0-9]*/\) .*|\1|p' "$tmp/web.err")
  [[ -n $url ]] || sleep 0.1
done
curl -fsS "${url}login.html" >"$tmp/login.html" || fail "GET ${url}login.html"
grep -qF "$marker" "$tmp/login.html" || fail "login.html was not the installed page"
curl -fsS "${url}vendor/chart.min.js" >"$tmp/chart.min.js" || fail "GET ${url}vendor/chart.min.js"
cmp -s "$tmp/chart.min.js" /usr/share/javascript/chart.js/chart.min.js || fail "Chart.js is not Debian's libjs-chart.js"
kill -TERM "$web_pid"
wait "$web_pid" || fail "trueaxis web did not stop cleanly on SIGTERM"

# The default machine of `sim shop` is the installed example (no examples/ in the working folder).
port=$(free_port)
"$bin" sim shop --machines 1 --base-port "$port" --duration-s 0.5 --status-interval-s 0 >"$tmp/shop.out" 2>&1 \
  || { cat "$tmp/shop.out"; fail "sim shop with the installed example machine"; }

# The shipped terminal.toml runs (on the example's 1-Wire tree and a free port instead of 502).
port=$(free_port)
"$bin" terminal --config "$moved/etc/trueaxis/terminal.toml" --one-wire-root "$moved/share/trueaxis/examples/terminal/w1_devices" \
  --port "$port" --duration-s 0.5 --status-interval-s 0 >"$tmp/terminal.out" 2>&1 || { cat "$tmp/terminal.out"; fail "terminal with the shipped terminal.toml"; }
grep -q 'x_nut' "$tmp/terminal.out" || { cat "$tmp/terminal.out"; fail "the terminal did not serve the shipped channels"; }

# --- a binary copied alone finds no pages and says where it looked ---
mkdir -p "$tmp/lone/bin"
cp "$bin" "$tmp/lone/bin/trueaxis"
set +e
"$tmp/lone/bin/trueaxis" web --listen 127.0.0.1:0 --users "$tmp/users.db" --duration-s 1 >"$tmp/lone.out" 2>"$tmp/lone.err"
rc=$?
set -e
[[ $rc == 2 ]] || { cat "$tmp/lone.err"; fail "a lone binary without pages: exit $rc, not 2"; }
grep -qF "$tmp/lone/share/trueaxis/web" "$tmp/lone.err" || { cat "$tmp/lone.err"; fail "the error does not say where it looked"; }
grep -qF -- "--web-root" "$tmp/lone.err" || { cat "$tmp/lone.err"; fail "the error does not name --web-root"; }
# … and serves with --web-root.
"$tmp/lone/bin/trueaxis" web --listen 127.0.0.1:0 --users "$tmp/users.db" --web-root "$moved/share/trueaxis/web" \
  --duration-s 0.2 >/dev/null 2>"$tmp/lone2.err" || { cat "$tmp/lone2.err"; fail "a lone binary with --web-root"; }

echo "PASS: installed to $prefix, moved, served ${url}login.html from the installed pages"
