# Mounts inside a lane root, sourced by tools/run-lane.sh and tools/lane-root.sh (one copy of the logic):
#   lane_mount_proc ROOT; lane_bind ROOT SRC TARGET-INSIDE-ROOT; ...; lane_unmount_all
# Every mount is recorded and lane_unmount_all takes them down in reverse order (lazily if busy), so a
# caller's EXIT / INT / TERM trap that calls it leaves nothing mounted on any exit path.
lane_mounts=()
lane_mount_proc() {  # lane_mount_proc ROOT
  mkdir -p "$1/proc"
  mount -t proc proc "$1/proc"
  lane_mounts+=("$1/proc")
}
lane_bind() {  # lane_bind ROOT SRC TARGET-INSIDE-ROOT
  mkdir -p "$1$3"
  mount --bind "$2" "$1$3"
  lane_mounts+=("$1$3")
}
lane_unmount_all() {
  local i
  for ((i=${#lane_mounts[@]}-1; i>=0; i--)); do
    umount "${lane_mounts[i]}" 2>/dev/null || umount -l "${lane_mounts[i]}" 2>/dev/null || \
      echo "lane-mounts: could not unmount ${lane_mounts[i]}" >&2
  done
  lane_mounts=()
}
