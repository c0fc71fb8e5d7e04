#!/usr/bin/env bash
# Makes a two-frame KITTI raw drive from the shipped KITTI frames, for trying --kitti-raw without the raw data set:
# DIR/2011_09_26/2011_09_26_drive_0001_sync/{image_02,image_03,velodyne_points}/data/000000000{0,1}.{png,bin} (frames
# 000002 and 000046 of testdata/kitti) and DIR/2011_09_26/calib_{cam_to_cam,velo_to_cam}.txt in the raw files'
# format, written from testdata/kitti/calib.txt. Prints the drive folder.
#   tools/make_raw_drive.sh DIR
set -eo pipefail
cd "$(dirname "$0")/.."
DATE=${1:?output folder}/2011_09_26
DRIVE=$DATE/2011_09_26_drive_0001_sync
for d in image_02 image_03 velodyne_points; do mkdir -p "$DRIVE/$d/data"; done
n=0
for id in 000002 000046; do
  name=$(printf %010d $n); n=$((n + 1))
  cp testdata/kitti/image_2/${id}_10.png "$DRIVE/image_02/data/$name.png"
  cp testdata/kitti/image_3/${id}_10.png "$DRIVE/image_03/data/$name.png"
  cp testdata/kitti/velodyne/$id.bin "$DRIVE/velodyne_points/data/$name.bin"
done
C=testdata/kitti/calib.txt
val() { awk -v k="$1:" '$1 == k { $1 = ""; sub(/^ /, ""); print }' "$C"; }
{ echo "calib_time: 09-Jan-2012 13:57:47"
  echo "R_rect_00: $(val R0_rect)"
  echo "P_rect_02: $(val P2)"
  echo "P_rect_03: $(val P3)"; } > "$DATE/calib_cam_to_cam.txt"
tr=($(val Tr_velo_to_cam))
{ echo "calib_time: 15-Mar-2012 11:37:16"
  echo "R: ${tr[0]} ${tr[1]} ${tr[2]} ${tr[4]} ${tr[5]} ${tr[6]} ${tr[8]} ${tr[9]} ${tr[10]}"
  echo "T: ${tr[3]} ${tr[7]} ${tr[11]}"; } > "$DATE/calib_velo_to_cam.txt"
echo "$DRIVE"
