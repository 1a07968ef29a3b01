# Written by `penumbra bench accuracy`; `gnuplot llvmpipe.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe.png"
svg = "llvmpipe.svg"
width = 1320
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n256x256, lights (az,el) 10,45; 100,20, sample distance 1/256, tf mri_skin, Blinn-Phong on"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
panels = 2
modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 2
variant_kinds = ""
array panel_title[2] = ["ch2 (mean over 2 lights)", "ch2better (mean over 2 lights)"]
array y_range[2] = ["[10.0:54.0]", "[10.0:39.0]"]
array ref_panel[2] = [1, 2]
array ref_ms[2] = [474.355, 570.407]
array ref_text[2] = ["reference 1/256 (PSNR inf)", "reference 1/256 (PSNR inf)"]
array ref_row[2] = [0, 0]
$front << EOD
1 39.609 11.9079 "dvr"
1 78.9044 20.4401 "32/64"
1 154.706 21.5059 "phong"
1 163.557 21.9504 "64/128"
1 195.534 22.5391 "64/64"
1 226.436 46.1954 "32/128"
1 231.298 51.7106 "32/256"
2 79.5846 11.2591 "dvr"
2 100.348 21.3494 "32/128"
2 121.384 21.4618 "32/64"
2 176.422 22.2239 "64/128"
2 223.435 36.3099 "32/256"
2 343.968 36.5437 "32/256"
EOD
$all << EOD
1 1 39.609 11.9079
1 2 154.706 21.5059
1 3 78.9044 20.4401
1 3 109.523 20.2253
1 3 140.539 20.1360
1 3 195.534 22.5391
1 3 163.557 21.9504
1 3 298.556 21.6675
1 3 286.166 26.0408
1 3 251.521 24.7168
1 3 412.085 23.9300
1 3 642.16 30.0789
1 3 800.907 29.7993
1 3 842.388 28.1925
1 4 314.509 40.1411
1 4 226.436 46.1954
1 4 231.298 51.7106
1 4 252.422 37.4904
1 4 268.788 43.8672
1 4 291.182 49.8328
1 4 261.998 35.4346
1 4 305.315 41.5406
1 4 342.323 47.6253
1 4 311.398 34.3046
1 4 292.642 40.0321
1 4 250.736 45.8675
1 5 423.564 30.0089
1 5 289.677 29.8344
1 5 401.394 29.6215
1 5 338.444 32.2942
1 5 362.713 31.9121
1 5 375.993 31.5532
1 5 363.442 35.0538
1 5 398.619 35.7604
1 5 509.915 35.4448
1 5 449.913 35.9055
1 5 381.035 38.8330
1 5 451.891 39.3658
1 6 318.48 44.9299
1 6 300.795 45.4120
1 6 358.176 45.5507
1 6 353.106 45.8007
1 6 367.96 47.1980
1 6 417.623 47.7171
1 6 356.659 43.0727
1 6 422.534 47.9141
1 6 463.138 49.9050
1 6 397.206 38.4916
1 6 413.891 45.5229
1 6 407.862 48.8066
2 1 79.5846 11.2591
2 2 349.519 20.8493
2 3 121.384 21.4618
2 3 100.348 21.3494
2 3 108.14 21.3009
2 3 235.291 22.4358
2 3 176.422 22.2239
2 3 289.892 22.0947
2 3 385.75 24.5605
2 3 531.744 23.9205
2 3 550.805 23.5005
2 3 703.441 27.3194
2 3 946.453 27.1178
2 3 1403.3 26.4399
2 4 491.41 34.5497
2 4 393.88 35.6021
2 4 223.435 36.3099
2 4 524.736 33.4067
2 4 300.798 34.8430
2 4 317.669 35.8169
2 4 322.08 32.2510
2 4 381.876 34.1694
2 4 345.529 35.4916
2 4 319.36 31.4892
2 4 365.432 33.5480
2 4 363.336 35.3418
2 5 557.922 30.5128
2 5 490.094 30.6949
2 5 359.217 30.7254
2 5 333.627 31.2158
2 5 468.603 31.6446
2 5 406.685 31.7562
2 5 410.428 31.8761
2 5 429.941 32.7966
2 5 471.983 33.2019
2 5 401.489 31.8389
2 5 386.149 33.2652
2 5 564.011 33.9811
2 6 555.718 36.4199
2 6 441.469 36.4991
2 6 343.968 36.5437
2 6 311.872 35.4971
2 6 435.623 35.8254
2 6 392.956 35.9377
2 6 415.995 34.5436
2 6 480.988 35.2759
2 6 454.488 35.5785
2 6 282.657 33.5854
2 6 394.242 35.0403
2 6 506.111 35.7342
EOD
$own << EOD
1 1 39.609 11.9079
1 2 154.706 21.5059
1 3 78.9044 20.4401
1 3 163.557 21.9504
1 3 195.534 22.5391
1 3 251.521 24.7168
1 3 286.166 26.0408
1 3 642.16 30.0789
1 4 226.436 46.1954
1 4 231.298 51.7106
1 5 289.677 29.8344
1 5 338.444 32.2942
1 5 363.442 35.0538
1 5 381.035 38.8330
1 5 451.891 39.3658
1 6 300.795 45.4120
1 6 353.106 45.8007
1 6 367.96 47.1980
1 6 407.862 48.8066
1 6 463.138 49.9050
2 1 79.5846 11.2591
2 2 349.519 20.8493
2 3 100.348 21.3494
2 3 121.384 21.4618
2 3 176.422 22.2239
2 3 235.291 22.4358
2 3 385.75 24.5605
2 3 703.441 27.3194
2 4 223.435 36.3099
2 5 333.627 31.2158
2 5 386.149 33.2652
2 5 564.011 33.9811
2 6 282.657 33.5854
2 6 311.872 35.4971
2 6 343.968 36.5437
EOD
$variants << EOD
EOD

# The accuracy plot of `penumbra bench accuracy` (installed as share/penumbra/plots/accuracy.gp).
# The benchmark writes its data and these variables above this text, into one script:
#   png, svg            the images to write (no folder: run in their folder)
#   width               pixels; 620 per panel, at least 960
#   title_text          the figure's title; x_label the x axis's
#   panels              one per volume; panel_title[v], y_range[v] ("[low:high]" or "[*:*]")
#   modes               the measured modes, reference aside, as words; a mode's index is its word
#   style_modes, style_colours, style_points   every mode's plot colour and point type (the
#                       mode table's), as words in the same order
#   ref_count           references; ref_panel[r], ref_ms[r], ref_text[r], ref_row[r]
#   $front              panel, frame ms, PSNR, label: the Pareto front over all modes
#   $all                panel, mode, frame ms, PSNR: every setting (means over the lights)
#   $own                panel, mode, frame ms, PSNR: each mode's own Pareto front
#   $variants           panel, mode, ms, PSNR, kind: the settings that differ from the request's
#                       defaults, by kind: 1 without empty-space skipping, 2 jittered, 3 refined
#                       (ms: the still and its steps in all)
#   variant_kinds       the kinds $variants holds, as words
# One panel per volume: every setting of a mode as a small mark, the mode's own front as its
# curve, the front over all modes as a wide grey band, the reference's time as a vertical line
# (its PSNR is infinite), and the variants as open marks in their mode's colour.

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
        if (words(variant_kinds) > 0) {
            plot @common_plot, @variant_plot
        } else {
            plot @common_plot
        }
    }
    unset multiplot
}
set output
