#!/bin/bash
# install.deb (tests/install/CMakeLists.txt): `cpack -G DEB` from the build folder into a temporary
# folder, then each package read with dpkg-deb: its control fields, the files and units it installs,
# its conffiles and maintainer scripts, and the extracted program run from the extracted tree.
#   install_deb_test.sh CPACK BUILD_DIR VERSION HAVE_HAL(ON|OFF)
set -euo pipefail
cpack=$1 build=$2 version=$3 have_hal=$4

tmp=$(mktemp -d /tmp/trueaxis-install-deb.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

(cd "$build" && "$cpack" -G DEB -B "$tmp/out") >"$tmp/cpack.log" 2>&1 || { cat "$tmp/cpack.log"; fail "cpack -G DEB"; }
arch=$(dpkg --print-architecture)
deb=$tmp/out/trueaxis_${version}_${arch}.deb
[[ -f $deb ]] || { ls "$tmp/out"; fail "no $deb"; }

# --- control fields ---
[[ $(dpkg-deb -f "$deb" Package) == trueaxis ]] || fail "Package: $(dpkg-deb -f "$deb" Package)"
[[ $(dpkg-deb -f "$deb" Version) == "$version" ]] || fail "Version: $(dpkg-deb -f "$deb" Version)"
depends=$(dpkg-deb -f "$deb" Depends)
for d in adduser libjs-chart.js libc6 libstdc++6 libsqlite3-0 libmodbus5 libsodium23; do
  [[ ", $depends," == *", $d"[\ ,]* ]] || fail "Depends lacks $d: $depends"
done

# --- files ---
root=$tmp/root
dpkg-deb -x "$deb" "$root"
for f in usr/bin/trueaxis usr/share/trueaxis/web/login.html usr/share/trueaxis/examples/machines/vmc850.toml \
         usr/share/doc/trueaxis/docs/install.md etc/trueaxis/shop.toml etc/trueaxis/terminal.toml \
         etc/trueaxis/server.env etc/trueaxis/web.env; do
  [[ -f $root/$f ]] || fail "not in the package: /$f"
done
[[ ! -e $root/usr/bin/trueaxis-hal ]] || fail "trueaxis-hal belongs in the trueaxis-hal package"
for name in server terminal web; do
  unit=$root/lib/systemd/system/trueaxis-$name.service
  [[ -f $unit ]] || fail "not in the package: /lib/systemd/system/trueaxis-$name.service"
  [[ $(sed -n 's/^ExecStart=//p' "$unit") == "/usr/bin/trueaxis $name "* ]] || fail "$unit: ExecStart does not run /usr/bin/trueaxis $name"
  grep -qx 'User=trueaxis' "$unit" || fail "$unit: not run as trueaxis"
done
grep -q -- '--config /etc/trueaxis/shop.toml' "$root/lib/systemd/system/trueaxis-server.service" || fail "server unit: not /etc/trueaxis/shop.toml"
grep -q -- '--config /etc/trueaxis/terminal.toml' "$root/lib/systemd/system/trueaxis-terminal.service" || fail "terminal unit: not /etc/trueaxis/terminal.toml"
# The extracted program finds the extracted pages (relative to itself) and reports the version.
[[ $("$root/usr/bin/trueaxis" --version) == "trueaxis $version" ]] || fail "extracted trueaxis --version"

# --- conffiles and maintainer scripts ---
ctrl=$tmp/control
dpkg-deb -e "$deb" "$ctrl"
for f in shop.toml terminal.toml server.env web.env; do
  grep -qx "/etc/trueaxis/$f" "$ctrl/conffiles" || fail "/etc/trueaxis/$f is not a conffile"
done
while read -r f; do [[ -f $root$f ]] || fail "conffile $f is not in the package"; done <"$ctrl/conffiles"
for s in postinst prerm postrm; do
  [[ -x $ctrl/$s ]] || fail "no executable $s"
  sh -n "$ctrl/$s" || fail "$s: syntax"
done
grep -Eq 'adduser --system .*--home /var/lib/trueaxis .*--shell /usr/sbin/nologin trueaxis' "$ctrl/postinst" \
  || fail "postinst does not create the system user trueaxis (home /var/lib/trueaxis, no login)"
! grep -Eq 'systemctl (enable|start|restart)|deb-systemd-invoke start' "$ctrl/postinst" || fail "postinst starts or enables a service"
# postinst run against stand-ins of the commands it calls (nothing on this computer changes): a fresh
# install makes the user and its folder, a second configure with the user present does not add it again.
stubs=$tmp/stubs
mkdir -p "$stubs"
for cmd in adduser install systemctl; do printf '#!/bin/sh\necho "%s $*" >>"%s"\n' "$cmd" "$tmp/calls" >"$stubs/$cmd"; done
printf '#!/bin/sh\n[ -e "%s" ]\n' "$tmp/user-exists" >"$stubs/getent"
chmod +x "$stubs"/*
PATH=$stubs:/bin:/usr/bin sh "$ctrl/postinst" configure "" || fail "postinst configure (fresh) failed"
grep -qx 'adduser --system --group --home /var/lib/trueaxis --no-create-home --shell /usr/sbin/nologin trueaxis' "$tmp/calls" \
  || { cat "$tmp/calls"; fail "postinst did not add the system user trueaxis"; }
grep -qx 'install -d -o trueaxis -g trueaxis -m 0750 /var/lib/trueaxis' "$tmp/calls" || { cat "$tmp/calls"; fail "postinst did not make /var/lib/trueaxis"; }
! grep -Eq '^systemctl .*(enable|start)' "$tmp/calls" || { cat "$tmp/calls"; fail "postinst enabled or started a service"; }
: >"$tmp/calls"
touch "$tmp/user-exists"
PATH=$stubs:/bin:/usr/bin sh "$ctrl/postinst" configure "$version" || fail "postinst configure (upgrade) failed"
! grep -q '^adduser' "$tmp/calls" || fail "postinst added the user again on upgrade"

# --- the HAL programs, in their own package ---
if [[ $have_hal == ON ]]; then
  hal=$tmp/out/trueaxis-hal_${version}_${arch}.deb
  [[ -f $hal ]] || { ls "$tmp/out"; fail "no $hal"; }
  dpkg-deb -c "$hal" >"$tmp/hal.list"
  grep -q '\./usr/bin/trueaxis-hal$' "$tmp/hal.list" || fail "trueaxis-hal not in $hal"
  grep -q '\./usr/bin/trueaxis-hal-plant$' "$tmp/hal.list" || fail "trueaxis-hal-plant not in $hal"
  [[ $(dpkg-deb -f "$hal" Depends) == *linuxcnc-uspace* ]] || fail "trueaxis-hal does not depend on linuxcnc-uspace: $(dpkg-deb -f "$hal" Depends)"
fi
echo "PASS: $(cd "$tmp/out" && ls *.deb | tr '\n' ' ')($(du -k "$deb" | cut -f1) KiB)"
