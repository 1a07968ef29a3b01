#!/usr/bin/env bash
# Prints the Debian packages that hold the shared libraries BINARY links, one a line: what the
# runtime image installs, so it carries no -dev package and no compiler.
set -euo pipefail
binary="$1"
libraries=$(ldd "$binary" | awk '/=> \//{print $3}')
for library in $libraries; do
    # dpkg knows the path it installed: under merged /usr, /lib/x is /usr/lib/x and either may be
    # the one dpkg recorded.
    resolved=$(readlink -f "$library")
    for path in "$library" "$resolved" "${library#/usr}" "${resolved#/usr}" "/usr$library" \
            "/usr$resolved"; do
        if owner=$(dpkg-query -S "$path" 2>/dev/null); then
            echo "${owner%%:*}"
            continue 2
        fi
    done
    echo "runtime-packages: no Debian package holds $library" >&2
    exit 1
done | sort -u
