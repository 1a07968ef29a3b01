# Written by `penumbra bench accuracy`; `gnuplot llvmpipe.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the truth; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe.png"
svg = "llvmpipe.svg"
width = 1320
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45, sample distance 1/512, 1/256, tf mri_skin,ct_bone, Blinn-Phong on\nPSNR against the truth: reference at 1/1024, jittered, mean of 16 frames"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
y_label = "PSNR vs the converged truth, dB (higher is better); grey labels: n / R"
panels = 2
modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 0
variant_kinds = ""
array panel_title[2] = ["ch2", "cranium_ct"]
array y_range[2] = ["[12.0:55.0]", "[10.0:47.0]"]
$front << EOD
1 33.7933 13.1294 "dvr"
1 51.2099 18.9066 "phong"
1 53.2939 39.3152 "256/128"
1 57.2162 43.4141 "256/256"
1 103.663 47.6693 "256/256"
1 618.097 52.7013 "reference"
2 47.1864 11.9504 "dvr"
2 65.1699 18.3478 "32/64"
2 66.4182 19.3722 "phong"
2 68.1987 34.1741 "128/128"
2 73.3593 34.7345 "32/256"
2 77.7294 35.5570 "64/256"
2 79.7472 36.4205 "256/256"
2 112.381 37.2668 "128/128"
2 116.026 41.2056 "64/256"
2 143.759 41.7180 "256/256"
2 163.201 42.1897 "256/256"
2 607.637 44.8551 "reference"
EOD
$all << EOD
1 1 53.1259 13.1825
1 1 33.7933 13.1294
1 2 76.4088 18.9825
1 2 51.2099 18.9066
1 3 103.641 17.7705
1 3 96.2829 17.7705
1 3 95.7547 17.6362
1 3 104.925 17.6362
1 3 130.869 17.5678
1 3 127.152 17.5678
1 3 187.788 19.2444
1 3 189.349 19.2444
1 3 211.274 18.9322
1 3 210.545 18.9322
1 3 288.697 18.7450
1 3 289.245 18.7450
1 3 305.925 22.1388
1 3 321.327 22.1388
1 3 387.349 21.3401
1 3 436.054 21.3401
1 3 419.969 20.9981
1 3 447.593 20.9981
1 3 680.826 26.9526
1 3 789.058 26.9526
1 3 752.024 25.9015
1 3 812.644 25.9015
1 3 1082.25 25.1627
1 3 1151.41 25.1627
1 4 137.527 39.2019
1 4 110.682 37.8790
1 4 163.728 43.0799
1 4 85.8059 40.5546
1 4 124.662 44.9838
1 4 88.3646 41.6212
1 4 126.225 36.8992
1 4 75.5751 36.0548
1 4 126.873 42.1695
1 4 76.7224 40.1209
1 4 146.56 45.4154
1 4 82.2793 42.0218
1 4 97.3963 35.3879
1 4 60.3009 34.7626
1 4 96.3929 41.3179
1 4 59.2885 39.6152
1 4 117.858 46.7746
1 4 66.9971 42.9984
1 4 121.338 34.5565
1 4 69.3715 33.9962
1 4 115.98 40.8525
1 4 53.2939 39.3152
1 4 103.663 47.6693
1 4 57.2162 43.4141
1 5 180.051 26.4390
1 5 97.9624 26.4710
1 5 177.171 26.2041
1 5 118.964 26.2367
1 5 175.976 26.0805
1 5 111.715 26.1140
1 5 168.608 27.9863
1 5 99.5851 28.0427
1 5 155.703 27.5808
1 5 98.6976 27.6476
1 5 192.258 27.3401
1 5 104.881 27.4102
1 5 125.257 31.4295
1 5 75.4369 31.5066
1 5 130.889 30.9431
1 5 84.0433 31.0636
1 5 169.613 30.5700
1 5 97.7588 30.7075
1 5 163.204 34.6724
1 5 101.532 34.6362
1 5 145.324 35.6498
1 5 73.3792 35.7447
1 5 153.538 35.3438
1 5 84.0381 35.4906
1 6 241.751 41.8658
1 6 139.281 39.5339
1 6 217.69 42.2268
1 6 119.693 39.7402
1 6 214.518 42.2830
1 6 107.09 39.7822
1 6 185.616 42.1630
1 6 107.398 39.6844
1 6 192.161 42.7346
1 6 108.575 40.0559
1 6 151.157 42.8677
1 6 88.9322 40.1387
1 6 152.118 42.3248
1 6 83.7283 40.0154
1 6 152.196 45.2329
1 6 96.9478 41.7950
1 6 159.433 45.8488
1 6 103.578 42.1621
1 6 169.593 38.8785
1 6 109.524 37.8136
1 6 170.515 45.3616
1 6 105.95 42.5876
1 6 168.525 46.4878
1 6 104.707 43.6028
1 7 618.097 52.7013
1 7 205.178 42.4481
2 1 68.453 12.0223
2 1 47.1864 11.9504
2 2 104.946 19.4979
2 2 66.4182 19.3722
2 3 69.45 18.3478
2 3 65.1699 18.3478
2 3 73.6989 18.2605
2 3 73.1284 18.2605
2 3 129.101 18.2069
2 3 135.928 18.2069
2 3 184.12 19.4281
2 3 185.389 19.4281
2 3 194.91 19.1806
2 3 194.342 19.1806
2 3 266.289 19.0515
2 3 238.7 19.0515
2 3 360.887 21.5079
2 3 361.604 21.5079
2 3 283.967 20.9916
2 3 325.763 20.9916
2 3 507.38 20.5973
2 3 435.076 20.5973
2 3 565.181 25.1609
2 3 566.474 25.1609
2 3 791.984 24.4310
2 3 724.833 24.4310
2 3 867.074 23.7489
2 3 947.712 23.7489
2 4 151.854 36.4121
2 4 100.38 33.0778
2 4 133.034 38.9185
2 4 78.6967 34.1936
2 4 144.632 40.6682
2 4 73.3593 34.7345
2 4 116.42 35.0891
2 4 98.1009 32.7837
2 4 126.838 38.2718
2 4 77.1359 34.4624
2 4 116.026 41.2056
2 4 77.7294 35.5570
2 4 122.26 33.6308
2 4 79.5647 31.9294
2 4 112.381 37.2668
2 4 68.1987 34.1741
2 4 119.388 40.9339
2 4 82.5942 35.7693
2 4 101.951 32.8336
2 4 76.0296 31.5777
2 4 133.63 36.9171
2 4 79.9809 34.3044
2 4 143.759 41.7180
2 4 79.7472 36.4205
2 5 171.532 27.5945
2 5 102.412 27.6703
2 5 129.406 27.3264
2 5 99.6258 27.4360
2 5 161.672 27.2537
2 5 104.753 27.3751
2 5 162.063 29.0474
2 5 98.9376 29.1031
2 5 153.534 28.6981
2 5 98.4481 28.8089
2 5 145.37 28.5847
2 5 97.9151 28.7251
2 5 152.607 31.0544
2 5 100.031 31.0094
2 5 137.718 31.0099
2 5 84.5022 31.1087
2 5 146.31 30.9547
2 5 86.3783 31.1174
2 5 125.173 32.9610
2 5 78.9755 32.6861
2 5 139.914 34.5746
2 5 104.587 34.3742
2 5 182.608 34.8805
2 5 98.3244 34.8019
2 6 168.919 38.3168
2 6 119.604 33.4475
2 6 178.522 38.3962
2 6 98.4514 33.4848
2 6 167.169 38.4980
2 6 109.856 33.5167
2 6 140.23 39.1358
2 6 107.173 34.1088
2 6 170.543 39.6670
2 6 104.703 34.2950
2 6 168.167 39.7962
2 6 106.516 34.3326
2 6 161.365 38.3140
2 6 100.971 33.7414
2 6 161.808 40.0428
2 6 93.6713 34.3233
2 6 136.237 40.4447
2 6 91.5294 34.4623
2 6 153.459 36.2745
2 6 112.194 33.6286
2 6 149.765 40.3434
2 6 83.7815 35.5413
2 6 163.201 42.1897
2 6 99.4414 36.2096
2 7 607.637 44.8551
2 7 208.519 33.5159
EOD
$own << EOD
1 1 33.7933 13.1294
1 1 53.1259 13.1825
1 2 51.2099 18.9066
1 2 76.4088 18.9825
1 3 95.7547 17.6362
1 3 96.2829 17.7705
1 3 187.788 19.2444
1 3 305.925 22.1388
1 3 680.826 26.9526
1 4 53.2939 39.3152
1 4 57.2162 43.4141
1 4 103.663 47.6693
1 5 73.3792 35.7447
1 6 83.7283 40.0154
1 6 88.9322 40.1387
1 6 96.9478 41.7950
1 6 103.578 42.1621
1 6 104.707 43.6028
1 6 152.196 45.2329
1 6 159.433 45.8488
1 6 168.525 46.4878
1 7 205.178 42.4481
1 7 618.097 52.7013
2 1 47.1864 11.9504
2 1 68.453 12.0223
2 2 66.4182 19.3722
2 2 104.946 19.4979
2 3 65.1699 18.3478
2 3 184.12 19.4281
2 3 283.967 20.9916
2 3 360.887 21.5079
2 3 565.181 25.1609
2 4 68.1987 34.1741
2 4 73.3593 34.7345
2 4 77.7294 35.5570
2 4 79.7472 36.4205
2 4 112.381 37.2668
2 4 116.026 41.2056
2 4 143.759 41.7180
2 5 78.9755 32.6861
2 5 98.3244 34.8019
2 5 182.608 34.8805
2 6 83.7815 35.5413
2 6 99.4414 36.2096
2 6 136.237 40.4447
2 6 163.201 42.1897
2 7 208.519 33.5159
2 7 607.637 44.8551
EOD
$variants << EOD
EOD

# The accuracy plot of `penumbra bench accuracy` (installed as share/penumbra/plots/accuracy.gp).
# The benchmark writes its data and these variables above this text, into one script:
#   png, svg            the images to write (no folder: run in their folder)
#   width               pixels; 620 per panel, at least 960
#   title_text          the figure's title; x_label and y_label the axes'
#   panels              one per volume; panel_title[v], y_range[v] ("[low:high]" or "[*:*]")
#   modes               the modes measured against a truth other than themselves, as words; a
#                       mode's index is its word
#   style_modes, style_colours, style_points   every mode's plot colour and point type (the
#                       mode table's), as words in the same order
#   ref_count           references that are the truth itself (a table measured without a
#                       converged truth); ref_panel[r], ref_ms[r], ref_text[r], ref_row[r]
#   $front              panel, frame ms, PSNR, label: the Pareto front over all modes
#   $all                panel, mode, frame ms, PSNR: every setting (means over the lights)
#   $own                panel, mode, frame ms, PSNR: each mode's own Pareto front
#   $variants           panel, mode, ms, PSNR, kind: the settings that differ from the request's
#                       defaults, by kind: 1 without empty-space skipping, 2 jittered, 3 refined
#                       (ms: the still and its steps in all)
#   variant_kinds       the kinds $variants holds, as words
# One panel per volume: every setting of a mode as a small mark, the mode's own front as its
# curve, the front over all modes as a wide grey band, a reference that is the truth itself as a
# vertical line at its time (its PSNR is infinite), and the variants as open marks in their mode's
# colour.

style_index(name) = sum [i=1:words(style_modes)] (word(style_modes, i) eq name ? i : 0)
colour(name) = style_index(name) > 0 ? word(style_colours, style_index(name)) : "#404040"
point(name) = style_index(name) > 0 ? int(word(style_points, style_index(name))) : 3
kind(k) = int(word(variant_kinds, k))
variant_point(kind) = kind == 1 ? 8 : (kind == 2 ? 10 : 12)
variant_title(kind) = kind == 1 ? "no empty-space skipping" : (kind == 2 ? "jittered" : "jittered and refined (time of all steps)")

# The plot's clauses, as macros: a plot with no variants leaves theirs out (gnuplot evaluates an
# iteration's clause once even when the iteration is empty).
common_plot = '$front using ($1 == v ? $2 : NaN):3 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", '. \
    '$front using ($1 == v ? $2 : NaN):3:4 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, '. \
    'for [m=1:words(modes)] $all using ($1 == v && $2 == m ? $3 : NaN):4 with points pt (point(word(modes, m)) - 1) ps 0.6 lc rgb colour(word(modes, m)) notitle, '. \
    'for [m=1:words(modes)] $own using ($1 == v && $2 == m ? $3 : NaN):4 with linespoints lw 2 pt point(word(modes, m)) ps 1.1 lc rgb colour(word(modes, m)) title word(modes, m)'
variant_plot = 'for [m=1:words(modes)] for [k=1:words(variant_kinds)] $variants using ($1 == v && $2 == m && $5 == kind(k) ? $3 : NaN):4 with points pt variant_point(kind(k)) ps 1.3 lw 1.5 lc rgb colour(word(modes, m)) notitle, '. \
    'for [k=1:words(variant_kinds)] NaN with points pt variant_point(kind(k)) ps 1.3 lw 1.5 lc rgb "#404040" title variant_title(kind(k))'

set logscale x
set grid xtics ytics mxtics lc rgb "#e8e8e8"
set xlabel x_label
set ylabel y_label
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
        if (words(variant_kinds) > 0) {
            plot @common_plot, @variant_plot
        } else {
            plot @common_plot
        }
    }
    unset multiplot
}
set output
