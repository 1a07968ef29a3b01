# Written by `penumbra bench accuracy`; `gnuplot llvmpipe.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front.
png = "llvmpipe.png"
svg = "llvmpipe.svg"
width = 1320
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45; 100,20, sample distance 1/256, tf mri_skin, Blinn-Phong on"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
panels = 2
modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone"
ref_count = 2
array panel_title[2] = ["ch2 (mean over 2 lights)", "ch2better (mean over 2 lights)"]
array y_range[2] = ["[10.0:51.0]", "[10.0:36.0]"]
array ref_panel[2] = [1, 2]
array ref_ms[2] = [217.335, 214.334]
array ref_text[2] = ["reference 1/256 (PSNR inf)", "reference 1/256 (PSNR inf)"]
array ref_row[2] = [0, 0]
$front << EOD
1 27.937 18.0593 "32/64"
1 56.4306 19.3508 "64/64"
1 115.68 21.7819 "128/64"
1 169.25 43.9725 "256/256"
1 175.128 44.4440 "32/128"
1 177.562 47.2499 "64/256"
1 177.817 48.3043 "32/256"
2 32.275 11.6772 "dvr"
2 33.9664 18.9580 "32/64"
2 65.2896 19.7327 "64/64"
2 132.515 20.9081 "128/64"
2 170.151 28.8911 "256/64"
2 171.698 30.6772 "64/64"
2 172.512 30.9822 "256/128"
2 172.737 32.6349 "256/256"
2 178.048 32.7711 "128/256"
2 183.35 33.5383 "32/256"
2 225.35 33.7248 "32/256"
EOD
$all << EOD
1 1 32.1417 11.9746
1 2 107.313 19.1356
1 3 27.937 18.0593
1 3 30.7575 17.9534
1 3 37.3159 17.9048
1 3 56.4306 19.3508
1 3 59.6218 19.0748
1 3 73.4087 18.9609
1 3 115.68 21.7819
1 3 130.979 21.1233
1 3 150.951 20.8722
1 3 226.118 25.9564
1 3 243.532 24.9377
1 3 290.403 24.3653
1 4 172.002 39.0138
1 4 175.128 44.4440
1 4 177.817 48.3043
1 4 173.455 36.5742
1 4 170.895 42.3856
1 4 177.562 47.2499
1 4 178.962 34.6279
1 4 181.546 40.2773
1 4 181.444 45.5418
1 4 171.938 33.6083
1 4 176.377 38.8908
1 4 169.25 43.9725
1 5 262.507 27.1675
1 5 269.903 26.9070
1 5 262.478 26.7756
1 5 264.426 29.1944
1 5 259.172 28.7061
1 5 270.232 28.4449
1 5 268.196 32.7588
1 5 270.522 32.4090
1 5 272.055 32.0741
1 5 263.997 35.1590
1 5 263.227 36.8403
1 5 258.466 36.9000
1 6 225.092 44.0340
1 6 223.437 44.3109
1 6 225.135 44.3727
1 6 209.614 44.7827
1 6 213.373 45.7235
1 6 225.222 46.0078
1 6 220.572 42.7161
1 6 221.741 46.6682
1 6 221.69 48.0709
1 6 213.209 38.2557
1 6 215.019 44.7197
1 6 203.757 46.8251
2 1 32.275 11.6772
2 2 112.053 18.8556
2 3 33.9664 18.9580
2 3 37.2597 18.8933
2 3 46.2829 18.8212
2 3 65.2896 19.7327
2 3 70.576 19.5462
2 3 88.2412 19.4630
2 3 132.515 20.9081
2 3 137.016 20.5967
2 3 161.832 20.4129
2 3 252.006 23.0130
2 3 257.345 22.8304
2 3 325.993 22.5135
2 4 184.113 31.8144
2 4 186.723 32.9184
2 4 183.35 33.5383
2 4 171.698 30.6772
2 4 178.766 32.1562
2 4 185.356 33.0698
2 4 184.034 29.6768
2 4 179.774 31.5307
2 4 178.048 32.7711
2 4 170.151 28.8911
2 4 172.512 30.9822
2 4 172.737 32.6349
2 5 264.685 26.9198
2 5 273.633 27.0304
2 5 272.981 27.0171
2 5 252.745 27.6090
2 5 266.629 27.9220
2 5 272.453 27.9593
2 5 267.675 28.5735
2 5 263.527 29.3335
2 5 264.336 29.5945
2 5 254.99 28.8279
2 5 262.729 30.1923
2 5 271.246 30.7831
2 6 229.99 33.6214
2 6 235.36 33.6886
2 6 225.35 33.7248
2 6 215.136 32.8312
2 6 226.855 33.1043
2 6 230.771 33.2021
2 6 218.464 31.8167
2 6 221.277 32.5610
2 6 217.92 32.8056
2 6 205.383 30.9771
2 6 213.947 32.4021
2 6 215.133 33.0035
EOD
$own << EOD
1 1 32.1417 11.9746
1 2 107.313 19.1356
1 3 27.937 18.0593
1 3 56.4306 19.3508
1 3 115.68 21.7819
1 3 226.118 25.9564
1 4 169.25 43.9725
1 4 175.128 44.4440
1 4 177.562 47.2499
1 4 177.817 48.3043
1 5 258.466 36.9000
1 6 203.757 46.8251
1 6 221.69 48.0709
2 1 32.275 11.6772
2 2 112.053 18.8556
2 3 33.9664 18.9580
2 3 65.2896 19.7327
2 3 132.515 20.9081
2 3 252.006 23.0130
2 4 170.151 28.8911
2 4 171.698 30.6772
2 4 172.512 30.9822
2 4 172.737 32.6349
2 4 178.048 32.7711
2 4 183.35 33.5383
2 5 252.745 27.6090
2 5 254.99 28.8279
2 5 262.729 30.1923
2 5 271.246 30.7831
2 6 205.383 30.9771
2 6 213.947 32.4021
2 6 215.133 33.0035
2 6 225.35 33.7248
EOD

# The accuracy plot of `penumbra bench accuracy` (installed as share/penumbra/plots/accuracy.gp).
# The benchmark writes its data and these variables above this text, into one script:
#   png, svg            the images to write (no folder: run in their folder)
#   width               pixels; 620 per panel
#   title_text          the figure's title; x_label the x axis's
#   panels              one per volume; panel_title[v], y_range[v] ("[low:high]" or "[*:*]")
#   modes               the measured modes, reference aside, as words; a mode's index is its word
#   ref_count           references; ref_panel[r], ref_ms[r], ref_text[r], ref_row[r]
#   $front              panel, frame ms, PSNR, label: the Pareto front over all modes
#   $all                panel, mode, frame ms, PSNR: every setting (means over the lights)
#   $own                panel, mode, frame ms, PSNR: each mode's own Pareto front
# One panel per volume: every setting of a mode as a small mark, the mode's own front as its
# curve, the front over all modes as a wide grey band, the reference's time as a vertical line
# (its PSNR is infinite).

style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0"
style_points = "5 7 9 11 13 15"
style_index(name) = sum [i=1:words(style_modes)] (word(style_modes, i) eq name ? i : 0)
colour(name) = style_index(name) > 0 ? word(style_colours, style_index(name)) : "#404040"
point(name) = style_index(name) > 0 ? int(word(style_points, style_index(name))) : 3

set logscale x
set grid xtics ytics mxtics lc rgb "#e8e8e8"
set xlabel x_label
set ylabel "PSNR vs reference, dB (higher is better); grey labels: slices n / light-buffer R"
set key bottom right box opaque font ",9" spacing 1.1
set mxtics 10

do for [pass=1:2] {
    if (pass == 1) {
        set terminal pngcairo size width,600 noenhanced font "DejaVu Sans,10"
        set output png
    } else {
        set terminal svg size width,600 dynamic noenhanced font "DejaVu Sans,10" background "#ffffff"
        set output svg
    }
    set multiplot layout 1,panels title title_text font ",12"
    do for [v=1:panels] {
        set title panel_title[v]
        unset arrow
        unset label
        eval "set yrange " . y_range[v]
        do for [r=1:ref_count] {
            if (ref_panel[r] == v) {
                set arrow from ref_ms[r], graph 0 to ref_ms[r], graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
                set label ref_text[r] at ref_ms[r], graph (0.97 - 0.05 * ref_row[r]) right offset -0.5,0 tc rgb "#c00000" font ",9"
            }
        }
        plot $front using ($1 == v ? $2 : NaN):3 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", \
             $front using ($1 == v ? $2 : NaN):3:4 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, \
             for [m=1:words(modes)] $all using ($1 == v && $2 == m ? $3 : NaN):4 with points pt (point(word(modes, m)) - 1) ps 0.6 lc rgb colour(word(modes, m)) notitle, \
             for [m=1:words(modes)] $own using ($1 == v && $2 == m ? $3 : NaN):4 with linespoints lw 2 pt point(word(modes, m)) ps 1.1 lc rgb colour(word(modes, m)) title word(modes, m)
    }
    unset multiplot
}
set output
