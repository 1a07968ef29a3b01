# Written by `penumbra bench accuracy`; `gnuplot llvmpipe_mri_brain.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the truth; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe_mri_brain.png"
svg = "llvmpipe_mri_brain.svg"
width = 960
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n128x128, lights (az,el) 10,45, sample distance 1/512, 1/256, tf mri_brain, Blinn-Phong on\nPSNR against the truth: reference at 1/1024, jittered, mean of 16 frames"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
y_label = "PSNR vs the converged truth, dB (higher is better); grey labels: n / R"
panels = 1
modes = "phong half_angle sbrc sbrc_cone reference"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 0
variant_kinds = "1 2 3"
array panel_title[1] = ["ch2bet"]
array y_range[1] = ["[20.0:57.0]"]
$front << EOD
1 24.8334 21.5748 "phong"
1 34.3664 44.9869 "64/128"
1 53.6492 46.4574 "256/128"
1 56.6935 48.0031 "64/128"
1 61.8475 49.1167 "32/128"
1 423.724 54.8993 "reference"
EOD
$all << EOD
1 1 39.5078 21.6279
1 1 24.8334 21.5748
1 2 41.6935 22.6475
1 2 39.0927 22.6475
1 2 79.5183 24.6868
1 2 84.8482 24.6868
1 2 156.883 29.3270
1 2 205.939 29.3270
1 2 327.158 34.9106
1 2 312.156 34.9106
1 3 61.8475 49.1167
1 3 60.7702 45.4598
1 3 56.6935 48.0031
1 3 34.3664 44.9869
1 3 91.7692 47.1786
1 3 43.127 44.7834
1 3 53.6492 46.4574
1 3 35.5481 44.4145
1 4 64.5524 47.1408
1 4 57.7205 44.2509
1 4 95.116 44.4815
1 4 57.2092 42.7630
1 4 96.7113 46.4989
1 4 62.0519 44.2481
1 4 81.6805 44.7540
1 4 49.0285 43.1133
1 5 423.724 54.8993
1 5 141.626 46.9396
EOD
$own << EOD
1 1 24.8334 21.5748
1 1 39.5078 21.6279
1 2 39.0927 22.6475
1 2 79.5183 24.6868
1 2 156.883 29.3270
1 2 312.156 34.9106
1 3 34.3664 44.9869
1 3 53.6492 46.4574
1 3 56.6935 48.0031
1 3 61.8475 49.1167
1 4 49.0285 43.1133
1 4 57.7205 44.2509
1 4 64.5524 47.1408
1 5 141.626 46.9396
1 5 423.724 54.8993
EOD
$variants << EOD
1 1 74.0575 21.6279 1
1 1 67.5562 21.6251 2
1 1 345.243 21.6351 3
1 1 618.711 21.6367 3
1 1 40.6431 21.6251 2
1 1 197.332 21.6351 3
1 1 355.198 21.6367 3
1 1 36.5375 21.5748 1
1 1 35.7944 21.6010 2
1 1 94.3537 21.6229 3
1 1 181.299 21.6240 3
1 1 27.9682 21.6010 2
1 1 130.214 21.6229 3
1 1 236.915 21.6240 3
1 2 42.1287 22.6475 1
1 2 43.4527 22.6475 1
1 2 88.3881 24.6868 1
1 2 79.7475 24.6868 1
1 2 194.653 29.3270 1
1 2 177.636 29.3270 1
1 2 296.715 34.9106 1
1 2 295.505 34.9106 1
1 3 98.6333 49.1167 1
1 3 90.1475 49.1038 2
1 3 317.528 50.2385 3
1 3 571.551 50.2686 3
1 3 84.6873 49.1038 2
1 3 335.477 50.2385 3
1 3 576.46 50.2686 3
1 3 49.9315 45.4598 1
1 3 24.8324 45.4070 2
1 3 193.077 50.0377 3
1 3 252.788 50.1262 3
1 3 37.052 45.4070 2
1 3 189.581 50.0377 3
1 3 342.634 50.1262 3
1 3 86.5883 48.0031 1
1 3 93.7385 47.9732 2
1 3 539.295 48.7989 3
1 3 863.866 48.8136 3
1 3 57.7063 47.9732 2
1 3 287.112 48.7989 3
1 3 516.802 48.8136 3
1 3 46.1035 44.9869 1
1 3 61.0322 44.9209 2
1 3 328.534 48.5836 3
1 3 493.456 48.6770 3
1 3 35.3413 44.9209 2
1 3 103.667 48.5836 3
1 3 196.823 48.6770 3
1 3 112.699 47.1786 1
1 3 126.043 47.2511 2
1 3 452.723 47.9410 3
1 3 832.593 47.9550 3
1 3 73.1198 47.2511 2
1 3 478.796 47.9410 3
1 3 782.779 47.9550 3
1 3 44.2762 44.7834 1
1 3 58.2449 44.6651 2
1 3 312.554 47.7713 3
1 3 471.29 47.8460 3
1 3 37.4919 44.6651 2
1 3 279.688 47.7713 3
1 3 452.366 47.8460 3
1 3 76.7253 46.4574 1
1 3 83.657 46.4713 2
1 3 413.822 47.0717 3
1 3 733.342 47.0865 3
1 3 52.3081 46.4713 2
1 3 275.628 47.0717 3
1 3 496.301 47.0865 3
1 3 44.4679 44.4145 1
1 3 47.2166 44.2819 2
1 3 222.513 46.9182 3
1 3 409.759 46.9695 3
1 3 33.1914 44.2819 2
1 3 161.531 46.9182 3
1 3 296.075 46.9695 3
1 4 152.598 47.1408 1
1 4 124.002 47.1298 2
1 4 606.797 47.7353 3
1 4 1241.31 47.7575 3
1 4 110.126 47.1298 2
1 4 594.874 47.7353 3
1 4 929.464 47.7575 3
1 4 91.177 44.2509 1
1 4 70.7799 44.1683 2
1 4 399.348 47.6121 3
1 4 596.344 47.6420 3
1 4 61.5733 44.1683 2
1 4 319.6 47.6121 3
1 4 558.75 47.6420 3
1 4 128.942 44.4815 1
1 4 132.822 44.4567 2
1 4 646.911 44.7534 3
1 4 1296.99 44.7769 3
1 4 91.3322 44.4567 2
1 4 468.133 44.7534 3
1 4 847.176 44.7769 3
1 4 90.7991 42.7630 1
1 4 77.3353 42.6088 2
1 4 265.17 44.7047 3
1 4 522.263 44.7159 3
1 4 59.6821 42.6088 2
1 4 241.966 44.7047 3
1 4 482.741 44.7159 3
1 4 120.932 46.4989 1
1 4 119.184 46.4689 2
1 4 586.646 47.0052 3
1 4 1061.75 47.0423 3
1 4 98.4166 46.4689 2
1 4 496.844 47.0052 3
1 4 915.147 47.0423 3
1 4 88.9165 44.2481 1
1 4 81.1872 44.1006 2
1 4 307.415 46.9356 3
1 4 553.874 46.9553 3
1 4 53.8355 44.1006 2
1 4 267.289 46.9356 3
1 4 481.121 46.9553 3
1 4 112.75 44.7540 1
1 4 117.472 44.7069 2
1 4 573.189 45.1551 3
1 4 1045.55 45.1600 3
1 4 89.6148 44.7069 2
1 4 413.995 45.1551 3
1 4 755.209 45.1600 3
1 4 62.6689 43.1133 1
1 4 66.9879 43.1101 2
1 4 587.152 45.1637 3
1 4 784.378 45.2053 3
1 4 54.41 43.1101 2
1 4 247.775 45.1637 3
1 4 453.847 45.2053 3
1 5 837.65 54.8993 1
1 5 165.993 46.9396 1
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
