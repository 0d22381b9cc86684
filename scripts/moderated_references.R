# Cross-check of data/diff/moderated.tsv.gz (made by scripts/moderated_references.py with
# inmoose) against R's own limma: Debian's r-bioc-limma (3.54.1 on bookworm).
#   apt-get update && apt-get install -y --no-install-recommends r-bioc-limma
#   Rscript scripts/moderated_references.R        # from the repository root
# Fits lmFit(~group) + eBayes() (trend=FALSE, robust=FALSE) on the inputs stored for each case
# (the rows whose `case` is its name; the replicate columns it lacks are `nan`) and stops unless
# every column, df_prior and s2_prior included, agrees to 1e-10 relative + 1e-12 absolute (the
# absolute part is for a coefficient that is exactly 0: inmoose's QR gives 8.9e-16 there).
suppressPackageStartupMessages(library(limma))
cat("limma", as.character(packageVersion("limma")), "\n")
close_enough <- function(a, b) all(abs(a - b) <= 1e-10 * pmax(abs(a), abs(b)) + 1e-12)
worst <- function(a, b) signif(max(abs(a - b) / (pmax(abs(a), abs(b)) + 1e-12)), 3)
all_cases <- read.delim(gzfile("data/diff/moderated.tsv.gz"), check.names = FALSE,
                        na.strings = "nan")
for (case in c("two_by_two", "three_by_three", "equal_variances")) {
  d <- all_cases[all_cases$case == case, ]
  if (nrow(d) == 0) stop(sprintf("no rows for %s", case))
  cols <- grep("^[AB][0-9]+$", names(d), value = TRUE)
  cols <- cols[colSums(!is.na(d[, cols])) > 0]  # the replicates the case has
  g <- factor(substr(cols, 1, 1))
  fit <- eBayes(lmFit(as.matrix(d[, cols]), model.matrix(~g)))
  got <- list(coefficient = fit$coefficients[, 2], stdev_unscaled = fit$stdev.unscaled[, 2],
              sigma = fit$sigma, df_residual = fit$df.residual, s2_post = fit$s2.post,
              df_total = fit$df.total, t = fit$t[, 2], p_value = fit$p.value[, 2])
  cat(case, " df.prior ", format(fit$df.prior, digits = 17), " s2.prior ",
      format(fit$s2.prior, digits = 17), "\n", sep = "")
  for (k in names(got)) {
    cat(sprintf("  %-15s worst relative difference %g\n", k, worst(got[[k]], d[[k]])))
    if (!close_enough(got[[k]], d[[k]])) stop(sprintf("%s: %s disagrees with R limma", case, k))
  }
  # df_prior is `inf` (read as Inf) for equal_variances
  for (k in c("df_prior", "s2_prior")) {
    want <- unique(d[[k]])
    have <- if (k == "df_prior") fit$df.prior else fit$s2.prior
    if (length(want) != 1) stop(sprintf("%s: %s differs between rows", case, k))
    if (is.infinite(want) || is.infinite(have)) {
      if (want != have) stop(sprintf("%s: %s disagrees with R limma", case, k))
    } else {
      cat(sprintf("  %-15s worst relative difference %g\n", k, worst(have, want)))
      if (!close_enough(have, want)) stop(sprintf("%s: %s disagrees with R limma", case, k))
    }
  }
}
cat("all cases agree with R limma\n")
