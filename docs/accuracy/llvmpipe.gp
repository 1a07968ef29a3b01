# Written by `penumbra bench accuracy`; `gnuplot llvmpipe.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached (wall clock: no GPU timers), y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front.
$v0_front << EOD
27.937 18.0593 "32/64"
56.4306 19.3508 "64/64"
115.68 21.7819 "128/64"
169.25 43.9725 "256/256"
175.128 44.4440 "32/128"
177.562 47.2499 "64/256"
177.817 48.3043 "32/256"
EOD
$v0_dvr_all << EOD
32.1417 11.9746 "dvr"
EOD
$v0_dvr_front << EOD
32.1417 11.9746 "dvr"
EOD
$v0_phong_all << EOD
107.313 19.1356 "phong"
EOD
$v0_phong_front << EOD
107.313 19.1356 "phong"
EOD
$v0_half_angle_all << EOD
27.937 18.0593 "32/64"
30.7575 17.9534 "32/128"
37.3159 17.9048 "32/256"
56.4306 19.3508 "64/64"
59.6218 19.0748 "64/128"
73.4087 18.9609 "64/256"
115.68 21.7819 "128/64"
130.979 21.1233 "128/128"
150.951 20.8722 "128/256"
226.118 25.9564 "256/64"
243.532 24.9377 "256/128"
290.403 24.3653 "256/256"
EOD
$v0_half_angle_front << EOD
27.937 18.0593 "32/64"
56.4306 19.3508 "64/64"
115.68 21.7819 "128/64"
226.118 25.9564 "256/64"
EOD
$v0_sbrc_all << EOD
172.002 39.0138 "32/64"
175.128 44.4440 "32/128"
177.817 48.3043 "32/256"
173.455 36.5742 "64/64"
170.895 42.3856 "64/128"
177.562 47.2499 "64/256"
178.962 34.6279 "128/64"
181.546 40.2773 "128/128"
181.444 45.5418 "128/256"
171.938 33.6083 "256/64"
176.377 38.8908 "256/128"
169.25 43.9725 "256/256"
EOD
$v0_sbrc_front << EOD
169.25 43.9725 "256/256"
175.128 44.4440 "32/128"
177.562 47.2499 "64/256"
177.817 48.3043 "32/256"
EOD
$v0_sbrc_shell_all << EOD
262.507 27.1675 "32/64"
269.903 26.9070 "32/128"
262.478 26.7756 "32/256"
264.426 29.1944 "64/64"
259.172 28.7061 "64/128"
270.232 28.4449 "64/256"
268.196 32.7588 "128/64"
270.522 32.4090 "128/128"
272.055 32.0741 "128/256"
263.997 35.1590 "256/64"
263.227 36.8403 "256/128"
258.466 36.9000 "256/256"
EOD
$v0_sbrc_shell_front << EOD
258.466 36.9000 "256/256"
EOD
$v0_sbrc_cone_all << EOD
225.092 44.0340 "32/64"
223.437 44.3109 "32/128"
225.135 44.3727 "32/256"
209.614 44.7827 "64/64"
213.373 45.7235 "64/128"
225.222 46.0078 "64/256"
220.572 42.7161 "128/64"
221.741 46.6682 "128/128"
221.69 48.0709 "128/256"
213.209 38.2557 "256/64"
215.019 44.7197 "256/128"
203.757 46.8251 "256/256"
EOD
$v0_sbrc_cone_front << EOD
203.757 46.8251 "256/256"
221.69 48.0709 "128/256"
EOD
$v1_front << EOD
32.275 11.6772 "dvr"
33.9664 18.9580 "32/64"
65.2896 19.7327 "64/64"
132.515 20.9081 "128/64"
170.151 28.8911 "256/64"
171.698 30.6772 "64/64"
172.512 30.9822 "256/128"
172.737 32.6349 "256/256"
178.048 32.7711 "128/256"
183.35 33.5383 "32/256"
225.35 33.7248 "32/256"
EOD
$v1_dvr_all << EOD
32.275 11.6772 "dvr"
EOD
$v1_dvr_front << EOD
32.275 11.6772 "dvr"
EOD
$v1_phong_all << EOD
112.053 18.8556 "phong"
EOD
$v1_phong_front << EOD
112.053 18.8556 "phong"
EOD
$v1_half_angle_all << EOD
33.9664 18.9580 "32/64"
37.2597 18.8933 "32/128"
46.2829 18.8212 "32/256"
65.2896 19.7327 "64/64"
70.576 19.5462 "64/128"
88.2412 19.4630 "64/256"
132.515 20.9081 "128/64"
137.016 20.5967 "128/128"
161.832 20.4129 "128/256"
252.006 23.0130 "256/64"
257.345 22.8304 "256/128"
325.993 22.5135 "256/256"
EOD
$v1_half_angle_front << EOD
33.9664 18.9580 "32/64"
65.2896 19.7327 "64/64"
132.515 20.9081 "128/64"
252.006 23.0130 "256/64"
EOD
$v1_sbrc_all << EOD
184.113 31.8144 "32/64"
186.723 32.9184 "32/128"
183.35 33.5383 "32/256"
171.698 30.6772 "64/64"
178.766 32.1562 "64/128"
185.356 33.0698 "64/256"
184.034 29.6768 "128/64"
179.774 31.5307 "128/128"
178.048 32.7711 "128/256"
170.151 28.8911 "256/64"
172.512 30.9822 "256/128"
172.737 32.6349 "256/256"
EOD
$v1_sbrc_front << EOD
170.151 28.8911 "256/64"
171.698 30.6772 "64/64"
172.512 30.9822 "256/128"
172.737 32.6349 "256/256"
178.048 32.7711 "128/256"
183.35 33.5383 "32/256"
EOD
$v1_sbrc_shell_all << EOD
264.685 26.9198 "32/64"
273.633 27.0304 "32/128"
272.981 27.0171 "32/256"
252.745 27.6090 "64/64"
266.629 27.9220 "64/128"
272.453 27.9593 "64/256"
267.675 28.5735 "128/64"
263.527 29.3335 "128/128"
264.336 29.5945 "128/256"
254.99 28.8279 "256/64"
262.729 30.1923 "256/128"
271.246 30.7831 "256/256"
EOD
$v1_sbrc_shell_front << EOD
252.745 27.6090 "64/64"
254.99 28.8279 "256/64"
262.729 30.1923 "256/128"
271.246 30.7831 "256/256"
EOD
$v1_sbrc_cone_all << EOD
229.99 33.6214 "32/64"
235.36 33.6886 "32/128"
225.35 33.7248 "32/256"
215.136 32.8312 "64/64"
226.855 33.1043 "64/128"
230.771 33.2021 "64/256"
218.464 31.8167 "128/64"
221.277 32.5610 "128/128"
217.92 32.8056 "128/256"
205.383 30.9771 "256/64"
213.947 32.4021 "256/128"
215.133 33.0035 "256/256"
EOD
$v1_sbrc_cone_front << EOD
205.383 30.9771 "256/64"
213.947 32.4021 "256/128"
215.133 33.0035 "256/256"
225.35 33.7248 "32/256"
EOD
set terminal pngcairo size 1320,600 noenhanced font "DejaVu Sans,10"
set output "llvmpipe.png"
set logscale x
set grid xtics ytics mxtics lc rgb "#e8e8e8"
set xlabel "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
set ylabel "PSNR vs reference, dB (higher is better); grey labels: slices n / light-buffer R"
set key bottom right box opaque font ",9" spacing 1.1
set mxtics 10
set multiplot layout 1,2 title "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45; 100,20, sample distance 1/256, tf mri_skin, Blinn-Phong on" font ",12"
set title "ch2 (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:51.0]
set arrow from 217.335, graph 0 to 217.335, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 217.335, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v0_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v0_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v0_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v0_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v0_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v0_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v0_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v0_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v0_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v0_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v0_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v0_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v0_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v0_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
set title "ch2better (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:36.0]
set arrow from 214.334, graph 0 to 214.334, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 214.334, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v1_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v1_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v1_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v1_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v1_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v1_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v1_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v1_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v1_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v1_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v1_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v1_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v1_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v1_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
unset multiplot
set terminal svg size 1320,600 dynamic noenhanced font "DejaVu Sans,10" background "#ffffff"
set output "llvmpipe.svg"
set multiplot layout 1,2 title "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45; 100,20, sample distance 1/256, tf mri_skin, Blinn-Phong on" font ",12"
set title "ch2 (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:51.0]
set arrow from 217.335, graph 0 to 217.335, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 217.335, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v0_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v0_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v0_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v0_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v0_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v0_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v0_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v0_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v0_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v0_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v0_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v0_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v0_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v0_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
set title "ch2better (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:36.0]
set arrow from 214.334, graph 0 to 214.334, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 214.334, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v1_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v1_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v1_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v1_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v1_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v1_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v1_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v1_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v1_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v1_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v1_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v1_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v1_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v1_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
unset multiplot
set output
