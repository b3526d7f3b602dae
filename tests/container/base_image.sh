# base_image.sh - sourced by verify_image.sh and tests/package/test_deb.sh:
# the tools (podman, runc, debootstrap, uidmap, mpirun) installed with apt
# when missing (root only; exit 77 to skip otherwise, 1 under
# RT_REQUIRE_ALL=1), and a local debian:bookworm-slim made with debootstrap,
# its tarball cached (no registry is reachable here).
# Needs: REPO, WORK, CACHE, BASE_TAR, BASE_IMAGE, NICE and log() set by the
# caller. Phase functions are called through the callers' timed().
# shellcheck disable=SC2317
phase_tools() {
    local missing=()
    command -v podman      >/dev/null || missing+=(podman)
    command -v runc        >/dev/null || missing+=(runc)
    command -v debootstrap >/dev/null || missing+=(debootstrap)
    command -v newuidmap   >/dev/null || missing+=(uidmap)
    command -v mpirun      >/dev/null || missing+=(openmpi-bin)
    if [ ${#missing[@]} -eq 0 ]; then
        log "tools present: $(podman --version), $(runc --version | head -n1)"
        return 0
    fi
    if [ "$(id -u)" -ne 0 ]; then
        log "missing ${missing[*]} and not root: cannot install"
        echo "SKIP: missing ${missing[*]} (run as root to install)"
        # In the test command (RT_REQUIRE_ALL=1) a skip is a failure.
        [ "${RT_REQUIRE_ALL:-0}" = 1 ] && exit 1
        exit 77
    fi
    log "installing: ${missing[*]}"
    "$REPO/scripts/install_packages.sh" "${missing[@]}" >"$WORK/apt.log" 2>&1 ||
        { tail -n 30 "$WORK/apt.log" >&2; return 1; }
}

# Mirror the host's apt configuration (the only network reachable here may be
# its configured Debian mirror).
host_mirror() {
    if [ -n "${RT_MPI_MIRROR:-}" ]; then echo "$RT_MPI_MIRROR"; return; fi
    local m=""
    if compgen -G '/etc/apt/sources.list.d/*.sources' >/dev/null; then
        m=$(awk '/^URIs:/ {print $2}' /etc/apt/sources.list.d/*.sources 2>/dev/null \
            | grep -E '/debian/?$' | head -n1 || true)
    fi
    if [ -z "$m" ] && [ -f /etc/apt/sources.list ]; then
        m=$(awk '$1=="deb" {for (i=2;i<=NF;i++) if ($i ~ /^(http|https|file):/) {print $i; break}}' \
            /etc/apt/sources.list | grep -E '/debian/?$' | head -n1 || true)
    fi
    echo "${m:-http://deb.debian.org/debian}"
}

make_base_tar() {
    local mirror root
    mirror=$(host_mirror); mirror=${mirror%/}
    root=$CACHE/rootfs.tmp
    case "$root" in /*/rootfs.tmp) ;; *) log "refusing odd rootfs path '$root'"; return 1 ;; esac
    mkdir -p "$CACHE"
    rm -rf "$root"
    log "debootstrap --variant=minbase bookworm from $mirror"
    nice -n "$NICE" debootstrap --variant=minbase bookworm "$root" "$mirror" >"$CACHE/debootstrap.log" 2>&1 \
        || { tail -n 30 "$CACHE/debootstrap.log" >&2; return 1; }
    # Make it look like the official debian:bookworm-slim: deb822 sources with
    # updates + security, no apt caches, no lists.
    rm -f "$root/etc/apt/sources.list"
    cat >"$root/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: ${RT_MPI_SECURITY_MIRROR:-${mirror}-security}
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    cat >"$root/etc/apt/apt.conf.d/docker-clean" <<'EOF'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache "";
Dir::Cache::srcpkgcache "";
EOF
    # Like the official -slim variant: keep docs/man/locales out of later installs.
    # (Existing copies in the rootfs are left alone; this only affects what the
    # Dockerfile's apt-get installs.)
    printf '%s\n' \
        'path-exclude /usr/share/doc/*' \
        'path-include /usr/share/doc/*/copyright' \
        'path-exclude /usr/share/man/*' \
        'path-exclude /usr/share/groff/*' \
        'path-exclude /usr/share/info/*' \
        'path-exclude /usr/share/lintian/*' \
        'path-exclude /usr/share/linda/*' \
        'path-exclude /usr/share/locale/*' \
        >"$root/etc/dpkg/dpkg.cfg.d/docker"
    rm -rf "${root:?}"/var/lib/apt/lists/* "${root:?}"/var/cache/apt/*.bin "${root:?}"/var/cache/apt/archives/*.deb \
           "${root:?}"/var/log/*.log "${root:?}"/var/log/apt/* "${root:?}"/dev/* "${root:?}"/proc/* "${root:?}"/sys/*
    tar --numeric-owner -C "$root" -cf "$BASE_TAR.tmp" .
    mv "$BASE_TAR.tmp" "$BASE_TAR"
    rm -rf "$root"
    log "base tarball: $BASE_TAR ($(du -h "$BASE_TAR" | cut -f1))"
}

phase_base() {
    if [ "${RT_MPI_REBUILD_BASE:-0}" = 1 ]; then
        rm -f "$BASE_TAR"
        podman image rm -f "$BASE_IMAGE" >/dev/null 2>&1 || true
    fi
    if podman image exists "$BASE_IMAGE"; then
        log "base image $BASE_IMAGE present"
        return 0
    fi
    [ -s "$BASE_TAR" ] || make_base_tar
    log "importing $BASE_TAR as $BASE_IMAGE"
    podman import \
        --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
        --change 'CMD ["bash"]' \
        "$BASE_TAR" "$BASE_IMAGE" >/dev/null
}
