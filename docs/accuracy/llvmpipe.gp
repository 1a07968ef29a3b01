# Written by `penumbra bench accuracy`; `gnuplot llvmpipe.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached (wall clock: no GPU timers), y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front.
$v0_front << EOD
42.0793 11.9746 "dvr"
56.1858 17.9534 "32/128"
61.4779 18.0593 "32/64"
101.482 19.3508 "64/64"
215.392 21.1233 "128/128"
219.586 28.2100 "256/128"
231.94 28.7833 "256/64"
330.885 30.2845 "256/128"
398.837 30.4059 "256/64"
EOD
$v0_dvr_all << EOD
42.0793 11.9746 "dvr"
EOD
$v0_dvr_front << EOD
42.0793 11.9746 "dvr"
EOD
$v0_phong_all << EOD
178.204 19.1356 "phong"
EOD
$v0_phong_front << EOD
178.204 19.1356 "phong"
EOD
$v0_half_angle_all << EOD
61.4779 18.0593 "32/64"
56.1858 17.9534 "32/128"
89.2162 17.9048 "32/256"
101.482 19.3508 "64/64"
121.93 19.0748 "64/128"
158.809 18.9609 "64/256"
259.024 21.7819 "128/64"
215.392 21.1233 "128/128"
404.808 20.8722 "128/256"
518.345 25.9564 "256/64"
396.127 24.9377 "256/128"
519.413 24.3653 "256/256"
EOD
$v0_half_angle_front << EOD
56.1858 17.9534 "32/128"
61.4779 18.0593 "32/64"
101.482 19.3508 "64/64"
215.392 21.1233 "128/128"
259.024 21.7819 "128/64"
396.127 24.9377 "256/128"
518.345 25.9564 "256/64"
EOD
$v0_sbrc_all << EOD
250.793 20.1214 "32/64"
292.549 19.9475 "32/128"
229.786 19.8834 "32/256"
236.984 21.4776 "64/64"
242.309 20.9837 "64/128"
236.198 20.8126 "64/256"
231.422 24.6428 "128/64"
228.724 23.6548 "128/128"
276.288 23.2242 "128/256"
231.94 28.7833 "256/64"
219.586 28.2100 "256/128"
247.363 27.5861 "256/256"
EOD
$v0_sbrc_front << EOD
219.586 28.2100 "256/128"
231.94 28.7833 "256/64"
EOD
$v0_sbrc_shell_all << EOD
376.937 20.2218 "32/64"
388.171 20.0654 "32/128"
349.146 20.0114 "32/256"
385.716 21.8419 "64/64"
345.526 21.4188 "64/128"
370.714 21.2802 "64/256"
371.802 25.6209 "128/64"
415.619 24.8995 "128/128"
418.804 24.6259 "128/256"
398.837 30.4059 "256/64"
330.885 30.2845 "256/128"
359.012 29.9781 "256/256"
EOD
$v0_sbrc_shell_front << EOD
330.885 30.2845 "256/128"
398.837 30.4059 "256/64"
EOD
$v0_sbrc_cone_all << EOD
313.621 19.5928 "32/64"
323.687 19.5746 "32/128"
336.433 19.5657 "32/256"
323.463 19.8240 "64/64"
329.993 19.7297 "64/128"
336.575 19.7058 "64/256"
353.365 20.7173 "128/64"
360.749 20.2935 "128/128"
338.214 20.1721 "128/256"
287.016 23.1505 "256/64"
303.08 22.1586 "256/128"
316.495 21.7746 "256/256"
EOD
$v0_sbrc_cone_front << EOD
287.016 23.1505 "256/64"
EOD
$v1_front << EOD
89.6347 11.6772 "dvr"
100.77 18.8933 "32/128"
106.944 18.9580 "32/64"
184.591 19.7327 "64/64"
319.847 23.3919 "128/64"
346.825 25.4852 "256/64"
357.718 25.7822 "256/256"
443.014 25.8890 "256/128"
501.511 26.3787 "256/64"
604.298 27.2777 "256/256"
EOD
$v1_dvr_all << EOD
89.6347 11.6772 "dvr"
EOD
$v1_dvr_front << EOD
89.6347 11.6772 "dvr"
EOD
$v1_phong_all << EOD
305.982 18.8556 "phong"
EOD
$v1_phong_front << EOD
305.982 18.8556 "phong"
EOD
$v1_half_angle_all << EOD
106.944 18.9580 "32/64"
100.77 18.8933 "32/128"
160.231 18.8212 "32/256"
184.591 19.7327 "64/64"
211.304 19.5462 "64/128"
312.797 19.4630 "64/256"
396.718 20.9081 "128/64"
376.928 20.5967 "128/128"
433.183 20.4129 "128/256"
681.203 23.0130 "256/64"
934.506 22.8304 "256/128"
1233.37 22.5135 "256/256"
EOD
$v1_half_angle_front << EOD
100.77 18.8933 "32/128"
106.944 18.9580 "32/64"
184.591 19.7327 "64/64"
376.928 20.5967 "128/128"
396.718 20.9081 "128/64"
681.203 23.0130 "256/64"
EOD
$v1_sbrc_all << EOD
389.265 20.9723 "32/64"
342.909 20.8512 "32/128"
390.225 20.8031 "32/256"
443.916 21.8618 "64/64"
357.849 21.5416 "64/128"
379.758 21.4434 "64/256"
319.847 23.3919 "128/64"
358.178 23.0014 "128/128"
435.566 22.7771 "128/256"
346.825 25.4852 "256/64"
443.014 25.8890 "256/128"
357.718 25.7822 "256/256"
EOD
$v1_sbrc_front << EOD
319.847 23.3919 "128/64"
346.825 25.4852 "256/64"
357.718 25.7822 "256/256"
443.014 25.8890 "256/128"
EOD
$v1_sbrc_shell_all << EOD
596.124 21.0493 "32/64"
491.301 20.9499 "32/128"
610.569 20.9227 "32/256"
685.719 22.1133 "64/64"
568.758 21.8631 "64/128"
523.71 21.8044 "64/256"
456.976 24.0428 "128/64"
499.018 23.9110 "128/128"
523.534 23.8577 "128/256"
501.511 26.3787 "256/64"
616.034 27.0983 "256/128"
604.298 27.2777 "256/256"
EOD
$v1_sbrc_shell_front << EOD
456.976 24.0428 "128/64"
501.511 26.3787 "256/64"
604.298 27.2777 "256/256"
EOD
$v1_sbrc_cone_all << EOD
429.366 20.4165 "32/64"
569.824 20.3988 "32/128"
461.573 20.3920 "32/256"
564.33 20.9895 "64/64"
354.001 20.9052 "64/128"
437.895 20.8930 "64/256"
408.544 21.5204 "128/64"
434.289 21.2916 "128/128"
503.955 21.2142 "128/256"
411.419 22.7040 "256/64"
521.761 22.2183 "256/128"
460.972 21.9655 "256/256"
EOD
$v1_sbrc_cone_front << EOD
354.001 20.9052 "64/128"
408.544 21.5204 "128/64"
411.419 22.7040 "256/64"
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
set yrange [10.0:33.0]
set arrow from 417.998, graph 0 to 417.998, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 417.998, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v0_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v0_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v0_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v0_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v0_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v0_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v0_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v0_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v0_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v0_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v0_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v0_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v0_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v0_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
set title "ch2better (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:30.0]
set arrow from 504.07, graph 0 to 504.07, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 504.07, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v1_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v1_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v1_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v1_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v1_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v1_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v1_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v1_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v1_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v1_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v1_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v1_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v1_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v1_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
unset multiplot
set terminal svg size 1320,600 dynamic noenhanced font "DejaVu Sans,10" background "#ffffff"
set output "llvmpipe.svg"
set multiplot layout 1,2 title "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45; 100,20, sample distance 1/256, tf mri_skin, Blinn-Phong on" font ",12"
set title "ch2 (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:33.0]
set arrow from 417.998, graph 0 to 417.998, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 417.998, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v0_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v0_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v0_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v0_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v0_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v0_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v0_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v0_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v0_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v0_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v0_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v0_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v0_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v0_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
set title "ch2better (mean over 2 lights)"
unset arrow
unset label
set yrange [10.0:30.0]
set arrow from 504.07, graph 0 to 504.07, graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
set label "reference 1/256 (PSNR inf)" at 504.07, graph 0.970 right offset -0.5,0 tc rgb "#c00000" font ",9"
plot $v1_front using 1:2 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", $v1_front using 1:2:3 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, $v1_dvr_all using 1:2 with points pt 4 ps 0.6 lc rgb "#7f7f7f" notitle, $v1_dvr_front using 1:2 with linespoints lw 2 pt 5 ps 1.1 lc rgb "#7f7f7f" title "dvr", $v1_phong_all using 1:2 with points pt 6 ps 0.6 lc rgb "#000000" notitle, $v1_phong_front using 1:2 with linespoints lw 2 pt 7 ps 1.1 lc rgb "#000000" title "phong", $v1_half_angle_all using 1:2 with points pt 8 ps 0.6 lc rgb "#e07b00" notitle, $v1_half_angle_front using 1:2 with linespoints lw 2 pt 9 ps 1.1 lc rgb "#e07b00" title "half_angle", $v1_sbrc_all using 1:2 with points pt 10 ps 0.6 lc rgb "#1f5fbf" notitle, $v1_sbrc_front using 1:2 with linespoints lw 2 pt 11 ps 1.1 lc rgb "#1f5fbf" title "sbrc", $v1_sbrc_shell_all using 1:2 with points pt 12 ps 0.6 lc rgb "#2a9d3a" notitle, $v1_sbrc_shell_front using 1:2 with linespoints lw 2 pt 13 ps 1.1 lc rgb "#2a9d3a" title "sbrc_shell", $v1_sbrc_cone_all using 1:2 with points pt 14 ps 0.6 lc rgb "#9b30c0" notitle, $v1_sbrc_cone_front using 1:2 with linespoints lw 2 pt 15 ps 1.1 lc rgb "#9b30c0" title "sbrc_cone"
unset multiplot
set output
