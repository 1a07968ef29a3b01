# Written by `penumbra bench accuracy`; `gnuplot llvmpipe_ct_soft_tissue.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the truth; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe_ct_soft_tissue.png"
svg = "llvmpipe_ct_soft_tissue.svg"
width = 960
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n128x128, lights (az,el) 10,45, sample distance 1/512, 1/256, tf ct_soft_tissue, Blinn-Phong on\nPSNR against the truth: reference at 1/1024, jittered, mean of 16 frames"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
y_label = "PSNR vs the converged truth, dB (higher is better); grey labels: n / R"
panels = 1
modes = "phong half_angle sbrc sbrc_cone reference"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 0
variant_kinds = "1 2 3"
array panel_title[1] = ["cranium_ct"]
array y_range[1] = ["[19.0:52.0]"]
$front << EOD
1 28.0156 40.4427 "256/128"
1 48.323 44.6712 "256/128"
1 70.3303 45.7919 "32/128"
1 708.022 48.1695 "reference"
EOD
$all << EOD
1 1 55.6151 22.3260
1 1 33.8914 22.2001
1 2 31.413 20.0634
1 2 36.6388 20.0634
1 2 79.5432 22.1106
1 2 80.5612 22.1106
1 2 113.461 26.9078
1 2 132.021 26.9078
1 2 143 32.6063
1 2 212.338 32.6063
1 3 70.3303 45.7919
1 3 37.8387 40.3975
1 3 88.7884 44.9329
1 3 56.3786 40.2883
1 3 76.933 44.5079
1 3 39.3312 40.2966
1 3 48.323 44.6712
1 3 28.0156 40.4427
1 4 135.992 44.7397
1 4 101.104 39.9595
1 4 142.223 45.4231
1 4 77.6429 40.3226
1 4 150.308 43.6735
1 4 61.3054 39.8874
1 4 75.2986 43.4365
1 4 34.1241 39.9511
1 5 708.022 48.1695
1 5 236.437 40.6696
EOD
$own << EOD
1 1 33.8914 22.2001
1 1 55.6151 22.3260
1 2 31.413 20.0634
1 2 79.5432 22.1106
1 2 113.461 26.9078
1 2 143 32.6063
1 3 28.0156 40.4427
1 3 48.323 44.6712
1 3 70.3303 45.7919
1 4 34.1241 39.9511
1 4 75.2986 43.4365
1 4 135.992 44.7397
1 4 142.223 45.4231
1 5 236.437 40.6696
1 5 708.022 48.1695
EOD
$variants << EOD
1 1 86.3347 22.3260 1
1 1 80.6363 22.3385 2
1 1 429.97 22.3609 3
1 1 756.767 22.3625 3
1 1 55.8741 22.3385 2
1 1 247.356 22.3609 3
1 1 450.593 22.3625 3
1 1 40.7444 22.2001 1
1 1 32.9031 22.2206 2
1 1 171.187 22.3234 3
1 1 310.859 22.3263 3
1 1 27.3206 22.2206 2
1 1 134.515 22.3234 3
1 1 282.619 22.3263 3
1 2 41.2822 20.0634 1
1 2 49.8887 20.0634 1
1 2 77.3358 22.1106 1
1 2 94.0918 22.1106 1
1 2 139.946 26.9078 1
1 2 112.352 26.9078 1
1 2 197.813 32.6063 1
1 2 210.926 32.6063 1
1 3 72.4192 45.7919 1
1 3 71.6747 45.7656 2
1 3 393.032 49.2297 3
1 3 729.414 49.2411 3
1 3 65.2825 45.7656 2
1 3 306.69 49.2297 3
1 3 566.181 49.2411 3
1 3 55.1618 40.3975 1
1 3 47.066 40.7041 2
1 3 266.264 48.7829 3
1 3 428.103 48.9374 3
1 3 69.3392 40.7041 2
1 3 286.762 48.7829 3
1 3 516.172 48.9374 3
1 3 113.165 44.9329 1
1 3 106.892 44.9083 2
1 3 541.201 47.5448 3
1 3 1006.83 47.5762 3
1 3 86.0009 44.9083 2
1 3 471.304 47.5448 3
1 3 859.543 47.5762 3
1 3 60.4821 40.2883 1
1 3 62.5802 40.6059 2
1 3 299.036 47.1541 3
1 3 529.009 47.2845 3
1 3 52.9113 40.6059 2
1 3 286.632 47.1541 3
1 3 511.463 47.2845 3
1 3 89.7429 44.5079 1
1 3 120.361 44.4629 2
1 3 538.049 46.6161 3
1 3 1013.7 46.6445 3
1 3 74.5547 44.4629 2
1 3 368.393 46.6161 3
1 3 673.582 46.6445 3
1 3 56.5642 40.2966 1
1 3 64.6354 40.6093 2
1 3 284.867 46.3281 3
1 3 486.166 46.4293 3
1 3 57.6721 40.6093 2
1 3 305.261 46.3281 3
1 3 455.582 46.4293 3
1 3 46.5718 44.6712 1
1 3 48.2074 44.6131 2
1 3 277.789 46.7202 3
1 3 469.013 46.7278 3
1 3 47.8626 44.6131 2
1 3 239.326 46.7202 3
1 3 430.786 46.7278 3
1 3 25.5994 40.4427 1
1 3 27.8445 40.8271 2
1 3 157.357 46.4349 3
1 3 285.735 46.5170 3
1 3 27.0468 40.8271 2
1 3 136.903 46.4349 3
1 3 247.26 46.5170 3
1 4 172.792 44.7397 1
1 4 258.363 44.8215 2
1 4 938.484 47.1986 3
1 4 1790.18 47.2145 3
1 4 109.972 44.8215 2
1 4 615.423 47.1986 3
1 4 1112.34 47.2145 3
1 4 106.869 39.9595 1
1 4 90.6309 40.3524 2
1 4 471.733 46.9081 3
1 4 887.029 47.0495 3
1 4 71.0746 40.3524 2
1 4 438.373 46.9081 3
1 4 831.705 47.0495 3
1 4 105.263 45.4231 1
1 4 106.02 45.4888 2
1 4 504.429 48.4027 3
1 4 947.787 48.4349 3
1 4 140.008 45.4888 2
1 4 714.707 48.4027 3
1 4 1295.09 48.4349 3
1 4 50.3182 40.3226 1
1 4 54.2105 40.5758 2
1 4 250.899 48.0564 3
1 4 456.916 48.2341 3
1 4 62.939 40.5758 2
1 4 248.434 48.0564 3
1 4 455.22 48.2341 3
1 4 145.933 43.6735 1
1 4 145.568 43.6846 2
1 4 614.722 45.3866 3
1 4 1089.33 45.4217 3
1 4 135.693 43.6846 2
1 4 708.383 45.3866 3
1 4 1188.77 45.4217 3
1 4 79.3272 39.8874 1
1 4 42.9756 40.0447 2
1 4 202.168 45.6538 3
1 4 365.486 45.7457 3
1 4 63.1241 40.0447 2
1 4 368.577 45.6538 3
1 4 663.158 45.7457 3
1 4 88.5479 43.4365 1
1 4 72.7663 43.4491 2
1 4 362.885 45.1865 3
1 4 655.172 45.1985 3
1 4 81.6521 43.4491 2
1 4 408.108 45.1865 3
1 4 734.595 45.1985 3
1 4 44.2982 39.9511 1
1 4 38.479 40.2094 2
1 4 195.544 45.3095 3
1 4 401.666 45.3836 3
1 4 45.4231 40.2094 2
1 4 222.305 45.3095 3
1 4 399.955 45.3836 3
1 5 1338.7 48.1695 1
1 5 269.918 40.6696 1
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
