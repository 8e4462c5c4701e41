# Sourced by the end-to-end test scripts.
# need_shared PATH...: the shared data the script reads (../shared/data beside
# the repository); a missing one fails the script at once, naming it.
need_shared() {
  local missing=0
  for p in "$@"; do
    if [ ! -e "$p" ]; then
      echo "FAILED: missing $p (the shared data, ../shared/data beside the repository)" >&2
      missing=1
    fi
  done
  if [ "$missing" -ne 0 ]; then
    echo "0 passed, 1 failed"
    exit 1
  fi
}

# need_colmap: the real COLMAP (Debian's colmap 3.8), run headless; without
# it the script fails at once and says why.
need_colmap() {
  if ! command -v colmap >/dev/null; then
    echo "FAILED: colmap is not installed (scripts/install-deps.sh installs Debian's colmap package)" >&2
    echo "0 passed, 1 failed"
    exit 1
  fi
  export QT_QPA_PLATFORM=offscreen
}

# ply_matches_points3d PLY POINTS3D_TXT: every vertex of a binary PLY (x y z
# as doubles, r g b) equals the X Y Z R G B of the same line of a COLMAP
# points3D.txt (coordinates to 1e-12 relative, colours exactly), and the
# counts agree. (perl: part of every Debian.)
ply_matches_points3d() {
  perl -e '
    local $/; open(my $f, "<", $ARGV[0]) or die; binmode $f; my $d = <$f>;
    my ($n) = $d =~ /element vertex (\d+)/; my $i = index($d, "end_header\n") + 11;
    open(my $t, "<", $ARGV[1]) or die; my @pts = grep { !/^#/ } split /\n/, <$t>;
    exit 1 if @pts != $n || length($d) != $i + 27 * $n;
    for my $k (0 .. $n - 1) {
      my @v = unpack("d<3 C3", substr($d, $i + 27 * $k, 27));
      my @w = (split / /, $pts[$k])[1 .. 6];
      for my $j (0 .. 2) { exit 1 if abs($v[$j] - $w[$j]) > 1e-12 * (1 + abs($w[$j])); }
      for my $j (3 .. 5) { exit 1 if $v[$j] != $w[$j]; }
    }' "$1" "$2"
}
