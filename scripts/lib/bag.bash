# shellcheck shell=bash
# The bag a replay plays through the graph (scripts/replay, scripts/capture): readable, and holding
# what the graph needs. After the devel space is sourced (rosbag):
#   check_bag PROG BAG   exits 2 naming what is wrong; else sets bag_info (rosbag info --yaml),
#                        images (image_rect, or image_raw for a rig's raw images), rectify
#                        (false/true) and bag_frames (left images)
bag_count() {  # TOPIC: messages on it in bag_info, 0 if absent
  echo "$bag_info" | awk -v t="$1" '$1 == "-" && $2 == "topic:" {on = ($3 == t)}
    on && $1 == "messages:" {print $2; exit}' | grep . || echo 0
}
check_bag() {
  local prog="$1" bag="$2" topic missing=()
  if ! bag_info="$(timeout 60 rosbag info --yaml "$bag" 2>&1)"; then
    echo "$prog: bag '$bag' is broken: $(echo "$bag_info" | grep -v '^\s*$' | tail -n 1)" >&2
    echo "$prog: (a truncated or unfinished bag may be repaired with: rosbag reindex '$bag')" >&2
    exit 2
  fi
  # Rectified images (the simulator's), or raw ones (a rig's, or pipeline.launch rectify:=true).
  images=image_rect rectify=false
  if [ "$(bag_count /stereo/left/image_rect)" -eq 0 ] && [ "$(bag_count /stereo/left/image_raw)" -gt 0 ]; then
    images=image_raw rectify=true
  fi
  for topic in /stereo/left/$images /stereo/right/$images /stereo/left/camera_info \
    /stereo/right/camera_info /tf_static /tf; do
    [ "$(bag_count "$topic")" -gt 0 ] || missing+=("$topic")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "$prog: bag '$bag' lacks ${missing[*]}: stereo needs both images (image_rect, or" \
      "image_raw to rectify) and camera infos, occlusion and eval the tf (/tf_static, /tf) that" \
      "pipeline.launch record:=FILE writes" >&2
    exit 2
  fi
  bag_frames=$(bag_count "/stereo/left/$images")
}
