#!/usr/bin/env bash
# Prints the Debian packages that hold the shared libraries BINARY links, one a line: what the
# runtime image installs, so it carries no -dev package and no compiler. Fails when a library
# belongs to no package.
set -euo pipefail
binary="$1"
libraries=$(ldd "$binary" | awk '/=> \//{print $3}')
# dpkg recorded each library under /lib or /usr/lib, which merged /usr makes one folder, and an
# alternative (liblapack.so.3) only as the file its link resolves to: look for all of those in
# dpkg's file lists, in one pass.
wanted=$(for library in $libraries; do
    for path in "$(readlink -f "$(dirname "$library")")/$(basename "$library")" \
            "$(readlink -f "$library")"; do
        echo "${path#/usr}"
        echo "/usr${path#/usr}"
    done
done)
found=$(grep -Fxo -f <(echo "$wanted") /var/lib/dpkg/info/*.list)
found_names=$(sed 's|.*/||' <<< "$found")
for library in $libraries; do
    if ! grep -qxF -e "$(basename "$library")" -e "$(basename "$(readlink -f "$library")")" \
            <<< "$found_names"; then
        echo "runtime-packages: no Debian package holds $library" >&2
        exit 1
    fi
done
# /var/lib/dpkg/info/libfoo1:amd64.list:/usr/lib/... -> libfoo1
sed -e 's|^/var/lib/dpkg/info/||' -e 's|\.list:.*||' -e 's|:.*||' <<< "$found" | sort -u
