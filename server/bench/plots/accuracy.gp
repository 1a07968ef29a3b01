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
