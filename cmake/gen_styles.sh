#!/usr/bin/env bash
# Register the project's styles with LIGGGHTS and regenerate its style_*.h headers.
#   gen_styles.sh LIGGGHTS_SRC PROJECT_STYLES VERSION_TEXT
# The project's headers are linked into LIGGGHTS_SRC so that LIGGGHTS' own Make.sh finds their
# *Style(...) macros. Make.sh only replaces a style_*.h whose content changed, but it rewrites
# version_liggghts.h every time (with a date); keep that file byte- and time-stable so that an
# unchanged tree recompiles nothing.
set -euo pipefail
lg=$1
styles=$(cd "$2" && pwd)
version=$3

cd "$lg"
# Drop links into the project tree (a style may have been renamed or removed), then relink.
find . -maxdepth 1 -type l -lname "$styles/*" -delete
for h in "$styles"/*.h; do
  [ -e "$h" ] || continue
  name=$(basename "$h")
  if [ -e "$name" ] && [ ! -L "$name" ]; then
    echo "gen_styles: error: liggghts_src/$name would shadow LIGGGHTS' own $name; rename it" >&2
    exit 1
  fi
  ln -sf "$h" "$name"
done

[ -f version_liggghts.h ] && cp -p version_liggghts.h .version_liggghts.h.keep
sh Make.sh style >/dev/null
printf '#define LIGGGHTS_VERSION "%s"\n' "$version" > .version_liggghts.h.new
if [ -f .version_liggghts.h.keep ] && cmp -s .version_liggghts.h.new .version_liggghts.h.keep; then
  mv .version_liggghts.h.keep version_liggghts.h
else
  mv .version_liggghts.h.new version_liggghts.h
fi
rm -f .version_liggghts.h.new .version_liggghts.h.keep
