"""The French text of every mistake a check can name (MISTAKES_FR, by id): the same ids and {placeholders} as the
English of each Mistake in mistakes.py, in the slides' words ("vous" throughout), as french.py is for the other
texts."""

MISTAKES_FR = {
    # --- box_inertia
    "box_not_squared": "les côtés doivent être au carré : I_xx = M/12 · (b² + c²), pas M/12 · (b + c) (une inertie "
                       "s'exprime en kg·m²)",
    "box_wrong_pairing": "les côtés sont mal associés : le moment autour d'un axe utilise les deux côtés "
                         "perpendiculaires à cet axe — I_xx = M/12 (b² + c²), I_yy = M/12 (a² + c²), "
                         "I_zz = M/12 (a² + b²) pour les côtés a, b, c selon x, y, z",
    "box_missing_twelfth": "le facteur 1/12 manque : I_body = M/12 · diag(b² + c², a² + c², a² + b²)",
    "box_half_sizes": "vous avez pris les demi-côtés (a/2, b/2, c/2) dans M/12 (b² + c²) : la formule prend les "
                      "longueurs entières des côtés",
    "box_missing_mass": "la masse M manque : I_body = M/12 · diag(b² + c², a² + c², a² + b²)",
    "box_moments_not_matrix": "vous avez renvoyé les trois moments : renvoyez la matrice 3×3 "
                              "I_body = np.diag([I_xx, I_yy, I_zz])",
    # --- velocity
    "velocity_times_mass": "v = P / M : vous avez multiplié P par M",
    "velocity_mass_over_P": "v = P / M, et non M / P",
    # --- inverse_inertia
    "I_body_as_world": "I⁻¹_body a été pris comme inertie dans l'espace monde (sans R … Rᵀ) : l'inertie du repère "
                       "objet tourne avec l'objet, I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ",
    "R_inverse_I_R": "la rotation est du mauvais côté : vous avez calculé R⁻¹ · I⁻¹_body · R (= Rᵀ · I⁻¹_body · R) ; "
                     "les slides donnent I⁻¹(t) = R · I⁻¹_body · Rᵀ, R à gauche",
    "missing_RT": "il manque Rᵀ à droite : I⁻¹(t) = R · I⁻¹_body · Rᵀ, et non R · I⁻¹_body",
    "inverse_inertia_not_inverted": "vous avez calculé I(t) = R · I_body · Rᵀ, le tenseur d'inertie lui-même : les "
                                    "slides veulent son inverse, I⁻¹(t) = R · I⁻¹_body · Rᵀ (inutile "
                                    "d'appeler np.linalg.inv)",
    "elementwise": "`*` multiplie les tableaux NumPy terme à terme : un produit matriciel s'écrit `@` "
                   "(R @ I_body_inv @ R.T, I_inv @ L)",
    # --- angular_velocity
    "omega_uses_inertia": "ω = I⁻¹(t) · L : vous avez multiplié L par I(t), l'inverse de I⁻¹(t)",
    # --- resultants
    "tau_sign": "τ a le mauvais signe : τ = (rᵢ − x) ∧ Fᵢ, le bras de levier d'abord ; vous avez calculé "
                "Fᵢ ∧ (rᵢ − x), ou (x − rᵢ) ∧ Fᵢ (un produit vectoriel change de signe quand on échange ses "
                "facteurs)",
    "lever_arm": "le bras de levier est rᵢ − x(t), du barycentre au point d'application de la force ; vous avez "
                 "pris rᵢ, ce qui donne le moment par rapport à l'origine du monde",
    "tau_sign_and_lever_arm": "deux erreurs dans τ : le bras de levier est rᵢ − x(t) (vous avez pris rᵢ) et il vient "
                              "en premier : τ = (rᵢ − x) ∧ Fᵢ (vous avez calculé Fᵢ ∧ rᵢ)",
    "last_force_only": "seule la dernière force compte dans vos sommes : F = Σ Fᵢ et τ = Σ (rᵢ − x) ∧ Fᵢ "
                       "additionnent toutes les forces (F += Fᵢ dans la boucle, pas F = Fᵢ)",
    "F_tau_swapped": "renvoyez (F, τ) dans cet ordre : vous avez renvoyé (τ, F)",
    "empty_forces": "sans force (forces = [], comme pour la boîte après sa poussée, partie 7), F et τ doivent être "
                    "des vecteurs nuls de forme (3,) : partez de np.zeros(3) pour les deux sommes (np.vstack et "
                    "np.stack refusent une liste vide, sum() de rien vaut l'entier 0)",
    # --- dxdt
    "R_dot_order": "Ṙ = ω* · R, avec ω* à gauche (chaque axe de l'objet, une colonne X' de R, tourne selon "
                   "dX'/dt = ω ∧ X') ; vous avez écrit R · ω*",
    "R_dot_missing_R": "Ṙ = ω* · R : vous avez renvoyé ω* seul",
    "omega_star_sign": "votre ω* a le mauvais signe (ou est transposé : ω*ᵀ = −ω*) : ω* a = ω ∧ a, donc "
                       "ω* = [[0, −ω_z, ω_y], [ω_z, 0, −ω_x], [−ω_y, ω_x, 0]]",
    "omega_from_P": "ω a été calculé à partir de P : ω(t) = I⁻¹(t) · L(t) — L (moment cinétique) porte la rotation, "
                    "P (quantité de mouvement) la translation",
    "v_from_L": "v a été calculé à partir de L : v(t) = P(t) / M — P (quantité de mouvement) porte la translation, "
                "L (moment cinétique) la rotation",
    "P_L_swapped": "P et L sont échangés : v = P / M (quantité de mouvement → translation) et ω = I⁻¹(t) · L "
                   "(moment cinétique → rotation)",
    "dx_is_P": "dx/dt = v = P / M : vous avez renvoyé P lui-même",
    "dP_is_acceleration": "dP/dt = F (P est une quantité de mouvement) : vous avez renvoyé F / M, une accélération",
    "dL_is_angular_acceleration": "dL/dt = τ (L est un moment cinétique) : vous avez renvoyé I⁻¹(t) · τ",
    # --- euler_step
    "R_not_updated": "R n'est pas mis à jour : R(t+Δt) = R(t) + Δt · ω* R(t) — sans cela l'objet ne tourne jamais",
    "x_not_updated": "x n'est pas mis à jour : x(t+Δt) = x(t) + Δt · v(t) — sans cela l'objet ne se déplace jamais",
    "P_not_updated": "P n'est pas mis à jour : P(t+Δt) = P(t) + Δt · F(t)",
    "L_not_updated": "L n'est pas mis à jour : L(t+Δt) = L(t) + Δt · τ(t)",
    "semi_implicit": "vous avez déplacé x ou R avec la nouvelle quantité de mouvement P(t+Δt) ou le nouveau moment "
                     "cinétique L(t+Δt) : c'est Euler semi-implicite. L'Euler explicite des slides prend tout "
                     "dX/dt = (v, ω* R, F, τ) dans X(t) — calculez-le d'abord, puis mettez à jour ; au repos, x et R "
                     "ne doivent pas bouger à la première itération",
    "no_dt": "les dérivées doivent être multipliées par Δt : X(t+Δt) = X(t) + Δt · dX/dt",
    "modified_input": "votre fonction a modifié son entrée sur place (x += …, P[:] = …, une liste complétée par "
                      "append) : créez de nouveaux tableaux (x_new = x + dt * v) — l'appelant a encore besoin de X(t)",
    # --- simulate
    "missing_initial": "les tableaux commencent à X₁ : ils doivent commencer par X₀ — n_steps pas donnent "
                       "n_steps + 1 états X₀, X₁, …, X_n",
    "missing_final": "le dernier état X_n manque : n_steps pas donnent n_steps + 1 états X₀, X₁, …, X_n",
    "wrong_length": "les tableaux doivent contenir n_steps + 1 états X₀, X₁, …, X_n",
    "aliasing": "tous les états enregistrés sont identiques (le dernier) : vous avez stocké des tableaux puis les "
                "avez modifiés sur place ; stockez de nouveaux tableaux (x = x + …, pas x += …) ou des copies",
    "wrong_time": "forces_at(t, X) a été appelée aux mauvais instants : le pas k commence à t = k · Δt "
                  "(0, Δt, 2Δt, …)",
    "stale_state": "forces_at(t, X) doit recevoir l'état courant X_k (le point rᵢ = x + R bᵢ d'une force se déplace "
                   "avec l'objet)",
    "ignores_step": "simulate n'a jamais appelé la fonction step qu'on lui a donnée : chaque itération est "
                    "X = step(M, I_body_inv, X, forces_at(t, X), dt), pour que la même boucle fasse tourner plus "
                    "tard le pas corrigé",
    "step_count": "step doit être appelée une fois par pas : n_steps fois",
    "no_step_parameter": "gardez la signature simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step) : "
                         "la vérification passe step=…",
    "forces_once": "forces_at n'a été appelée qu'une fois, avant la boucle : les forces changent avec t et avec "
                   "l'état (le point rᵢ = x + R bᵢ suit l'objet) — appelez forces_at(t, X) dans la boucle, à chaque "
                   "pas, avec le t et le X de ce pas",
    "returned_one_state": "elle a renvoyé un seul état, pas la liste des états : simulate renvoie les tableaux des "
                          "n_steps + 1 états X₀, X₁, …, X_n (x de forme (n_steps + 1, 3), R de forme "
                          "(n_steps + 1, 3, 3), …), pas seulement le dernier",
    "extra_step": "un pas de trop : n_steps pas donnent n_steps + 1 états X₀ … X_n, votre boucle en fait "
                  "n_steps + 1 (range(n_steps + 1) ?)",
    "ignores_dt": "le pas de temps dt donné à simulate n'est pas celui passé à step : chaque itération est "
                  "X = step(M, I_body_inv, X, forces_at(t, X), dt), avec ce dt-là",
    # --- project_so3 and the projected step
    "svd_V_transposed": "np.linalg.svd renvoie (U, S, Vᵀ) : sa troisième sortie est déjà Vᵀ, donc la rotation la plus "
                        "proche est U @ Vt (vous avez pris U @ Vt.T)",
    "svd_not_projected": "vous avez renvoyé R inchangée (U Σ Vᵀ, c'est R elle-même) : la rotation la plus proche "
                         "laisse tomber Σ, U Vᵀ",
    "columns_normalized": "normaliser les colonnes (ou les lignes) ne suffit pas : elles doivent aussi être "
                          "perpendiculaires (RᵀR = I) ; utilisez la SVD R = U Σ Vᵀ → U Vᵀ",
    "projection_transposed": "vous avez renvoyé la transposée de la rotation la plus proche : U Vᵀ, et non V Uᵀ",
    "not_nearest": "votre matrice est une rotation, mais pas la plus proche de R (une autre mise à jour de R, ou le "
                   "Q de np.linalg.qr, qui peut retourner des colonnes) : la correction change R le moins possible ; "
                   "utilisez la SVD R = U Σ Vᵀ → U Vᵀ",
    "not_a_rotation": "le résultat n'est pas une rotation (RᵀR ≠ I ou det R ≠ 1) ; utilisez la SVD "
                      "R = U Σ Vᵀ → U Vᵀ",
    "step_not_projected": "R(t+Δt) n'est pas projetée : appliquez project_so3 à R après le pas d'Euler",
    "projected_before": "projetez R après le pas d'Euler (c'est le pas qui fait sortir R de SO(3)), pas avant",
    # --- what a function returned
    "returned_list": "elle a renvoyé une liste Python, pas un tableau NumPy : plus loin `dt * v` lève une TypeError "
                     "et `x + v` met deux listes bout à bout ; renvoyez np.array([...]) (ou calculez avec des "
                     "tableaux : P / M)",
    "integer_array": "votre tableau contient des entiers (dtype int) : un tableau créé à partir d'entiers, "
                     "np.array([0, 0, 0]) ou np.zeros(3, dtype=int), tronque chaque valeur qu'on y écrit (0.7 → 0) ; "
                     "partez de flottants : np.zeros(3), np.array([0.0, 0.0, 0.0])",
    "complex_array": "votre tableau contient des nombres complexes (np.linalg.eig ? la racine carrée d'un nombre "
                     "négatif ?) : toutes les grandeurs ici sont réelles",
    "returned_matrix": "elle a renvoyé une np.matrix : utilisez des tableaux ordinaires (np.array) et `@` pour les "
                       "produits — avec np.matrix, `*` est un produit matriciel et les vecteurs deviennent des "
                       "matrices 1×3",
    "args_swapped": "arguments dans le mauvais ordre : votre fonction donne le bon résultat quand on échange ses "
                    "arguments ({detail}) ; gardez la signature de l'exercice {signature}",
    # --- box_inertia, more
    "box_inverted": "vous avez renvoyé l'inverse I_body⁻¹ : box_inertia renvoie I_body lui-même, "
                    "M/12 · diag(b² + c², a² + c², a² + b²) (l'inverse vient plus tard, I_body_inv)",
    "box_third": "M/3 va avec les demi-côtés (M/3 · ((b/2)² + (c/2)²)) ; avec les côtés entiers a, b, c, c'est "
                 "M/12 : I_body = M/12 · diag(b² + c², a² + c², a² + b²)",
    "box_one_moment": "{detail} : chaque moment utilise les deux côtés perpendiculaires à son axe, "
                      "I_xx = M/12 (b² + c²), I_yy = M/12 (a² + c²), I_zz = M/12 (a² + b²)",
    "box_sum_all": "chaque moment n'utilise que les deux côtés perpendiculaires à son axe : "
                   "I_xx = M/12 (b² + c²), et non M/12 (a² + b² + c²)",
    # --- velocity, more
    "velocity_no_mass": "v = P / M : vous avez renvoyé P lui-même (la quantité de mouvement, pas la vitesse) ; avec "
                        "M ≠ 1 elles diffèrent",
    "velocity_mass_squared": "v = P / M : vous avez divisé deux fois par M (P / M²)",
    "floor_division": "arithmétique entière : `//` est la division entière et int() tronque (les deux arrondissent à "
                      "l'entier inférieur) : divisez avec `/` et gardez des flottants (v = P / M, M / 12)",
    # --- inverse_inertia, more
    "R_inverse_not_transpose": "R⁻¹ au lieu de Rᵀ : les deux ne sont égales que pour une rotation exacte ; le R "
                               "d'Euler n'en est pas une (R + Δt ω* R sort de SO(3)), et alors R · I⁻¹_body · R⁻¹ "
                               "n'est plus le I⁻¹(t) = R · I⁻¹_body · Rᵀ des slides — écrivez R.T, pas "
                               "np.linalg.inv(R)",
    "missing_transpose": "la transposée manque : I⁻¹(t) = R · I⁻¹_body · Rᵀ, vous avez calculé R · I⁻¹_body · R "
                         "(R.T à droite)",
    "transpose_both": "seul le R de droite est transposé : I⁻¹(t) = R · I⁻¹_body · Rᵀ, vous avez calculé "
                      "Rᵀ · I⁻¹_body · Rᵀ",
    "missing_R_left": "il manque R à gauche : I⁻¹(t) = R · I⁻¹_body · Rᵀ, et non I⁻¹_body · Rᵀ "
                      "(ou Rᵀ · I⁻¹_body)",
    # --- resultants, more
    "tau_missing": "τ est nul : les moments n'ont jamais été additionnés, τ = Σ (rᵢ − x) ∧ Fᵢ",
    "lever_arm_plus": "le bras de levier est rᵢ − x(t), du barycentre au point : vous avez pris rᵢ + x(t)",
    "first_force_only": "seule la première force compte dans vos sommes : F = Σ Fᵢ et τ = Σ (rᵢ − x) ∧ Fᵢ "
                        "additionnent toutes les forces (un return dans la boucle ?)",
    "force_skipped": "une force manque dans vos sommes (range(len(forces) - 1) ? forces[1:] ?) : F = Σ Fᵢ et "
                     "τ = Σ (rᵢ − x) ∧ Fᵢ portent sur toutes les forces",
    "dot_for_cross": "τ est un vecteur : (rᵢ − x) ∧ Fᵢ est le produit vectoriel np.cross(r - x, F), pas le produit "
                     "scalaire np.dot (un nombre)",
    "tau_of_sums": "le moment de la somme n'est pas la somme des moments : τ = Σ (rᵢ − x) ∧ Fᵢ, chaque force avec son "
                   "propre bras de levier, et non (Σ rᵢ − x) ∧ Σ Fᵢ ou (r̄ − x) ∧ F",
    "force_pair_order": "chaque couple est (rᵢ, Fᵢ), le point d'abord : `for r, F in forces` ; vous les avez lus "
                        "comme (Fᵢ, rᵢ)",
    "forces_averaged": "F = Σ Fᵢ et τ = Σ (rᵢ − x) ∧ Fᵢ sont des sommes, pas des moyennes (pas de / len(forces))",
    # --- dxdt, more
    "R_dot_elementwise": "Ṙ = ω* · R est un produit matriciel : `ω* * R` multiplie terme à terme ; écrivez "
                         "star(omega) @ R",
    "star_wrong": "votre ω* n'est pas la matrice du produit vectoriel par ω (ω* a doit valoir ω ∧ a) : "
                  "ω* = [[0, −ω_z, ω_y], [ω_z, 0, −ω_x], [−ω_y, ω_x, 0]] — vérifiez chaque terme",
    "R_dot_is_omega": "dR/dt = ω* · R est une matrice 3×3 : vous avez renvoyé le vecteur ω",
    "R_dot_body_frame": "vous avez écrit Ṙ = R · (ω_body)* avec ω_body = I⁻¹_body Rᵀ L : c'est égal à ω* R "
                        "seulement tant que R est une rotation exacte, et le R d'Euler n'en est pas une ; les "
                        "slides donnent Ṙ = ω* · R avec le ω du monde",
    "cross_rows": "np.cross(omega, R) fait le produit vectoriel de ω avec chaque ligne de R, mais les axes de "
                  "l'objet X', Y', Z' sont les colonnes de R : Ṙ = ω* · R = star(omega) @ R (ou "
                  "np.cross(omega, R, axis=0))",
    "R_dot_transposed": "vous avez renvoyé (ω* R)ᵀ : Ṙ = ω* · R, pas sa transposée (chaque colonne de R, un axe de "
                        "l'objet, tourne selon dX'/dt = ω ∧ X')",
    "dP_times_mass": "dP/dt = F : vous avez multiplié F par M",
    "rates_order": "renvoyez les dérivées dans l'ordre de l'état (v, ω* R, F, τ) : vous avez renvoyé τ avant F",
    "dP_is_P": "dP/dt = F : vous avez renvoyé P lui-même",
    "dL_is_L": "dL/dt = τ : vous avez renvoyé L lui-même",
    # --- euler_step, more
    "L_step_uses_F": "L(t+Δt) = L(t) + Δt · τ(t) : vous avez ajouté Δt · F (la force, pas le moment)",
    "P_step_uses_tau": "P(t+Δt) = P(t) + Δt · F(t) : vous avez ajouté Δt · τ (le moment, pas la force)",
    "dt_twice": "Δt est appliqué deux fois (Δt² · dX/dt) : X(t+Δt) = X(t) + Δt · dX/dt, une seule fois — votre "
                "dxdt multipliait-il déjà par dt ?",
    "R_exact_rotation": "vous avez tourné R d'une rotation exacte (expm(Δt ω*) · R, ou Rodrigues) : le pas d'Euler "
                        "des slides est R(t+Δt) = R(t) + Δt · ω* R(t) — sa dérive hors de SO(3) est ce "
                        "qu'étudie la partie 8",
    "projected_in_euler_step": "vous avez reprojeté R sur SO(3) dans euler_step : le pas d'Euler des slides "
                               "est R + Δt · ω* R, sans projection ; la projection est la correction de la partie 8 "
                               "(euler_step_projected)",
    "R_dot_times_R": "Ṙ = ω* R contient déjà R : R(t+Δt) = R + Δt · Ṙ, et non R + Δt · Ṙ · R",
    "rates_after_update": "τ a été calculé par rapport au nouveau x(t+Δt) : l'Euler explicite des slides prend "
                          "tout dX/dt = (v, ω* R, F, τ) dans X(t) — calculez-le d'abord, puis mettez à jour x, R, P, L",
    "half_step": "vous avez avancé de Δt/2 : X(t+Δt) = X(t) + Δt · dX/dt, un pas entier",
    "state_order": "renvoyez le nouvel état dans l'ordre X = (x, R, P, L)",
    "scaled": "votre résultat vaut {detail} × le bon : la formule est juste à un facteur constant près — cherchez "
              "un facteur en trop ou manquant",
    "rounded": "votre résultat est arrondi ({detail}) : renvoyez la valeur en pleine précision (pas de np.round, "
               "int() ni chaînes formatées)",
    "returned_rates": "vous avez renvoyé dX/dt, les dérivées : euler_step renvoie le nouvel état "
                      "X(t+Δt) = X(t) + Δt · dX/dt",
    "returned_increment": "vous avez renvoyé Δt · dX/dt, la variation seule : ajoutez-la à X(t), "
                          "X(t+Δt) = X(t) + Δt · dX/dt",
    "euler_minus": "X(t+Δt) = X(t) + Δt · dX/dt : vous avez soustrait les dérivées (le temps recule)",
    # --- project_so3, more
    "svd_no_det_fix": "ici det(U Vᵀ) = −1 et U Vᵀ est une réflexion, pas une rotation : changez le signe de la "
                      "dernière colonne de U (la plus petite valeur singulière) quand det(U Vᵀ) < 0, puis U Vᵀ",
    "svd_negated": "−U Vᵀ a un déterminant +1 mais est loin de R (il retourne chaque axe) : quand det(U Vᵀ) < 0, "
                   "changez le signe de la seule dernière colonne de U (la plus petite valeur singulière)",
    "svd_wrong_column": "quand det(U Vᵀ) < 0, changez le signe de la colonne de U qui va avec la plus petite valeur "
                        "singulière, la dernière (U[:, 2]), pas la première ni la deuxième",
    "svd_flip_always": "changez le signe de la dernière colonne de U seulement quand det(U Vᵀ) < 0 : fait à chaque "
                       "fois, U diag(1, 1, −1) Vᵀ est une réflexion dès que U Vᵀ est déjà une rotation",
    "svd_factors_swapped": "la rotation la plus proche est U @ Vt (U d'abord) : vous avez calculé Vt @ U",
    "svd_U_only": "U seule n'est pas la rotation la plus proche : R = U Σ Vᵀ → U Vᵀ (gardez Vᵀ, laissez tomber Σ)",
    "scaled_by_det": "diviser R par det(R)^(1/3) corrige son volume, pas ses angles (RᵀR ≠ I toujours) : utilisez "
                     "la SVD R = U Σ Vᵀ → U Vᵀ",
    # --- issue 30: the families of slips
    "precedence": "priorité des opérateurs : `M/12*b**2 + c**2` vaut (M/12)·b² + c² — la somme a besoin de ses "
                  "parenthèses, M/12 * (b**2 + c**2)",
    "square_of_sum": "(b + c)² n'est pas b² + c² : mettez chaque côté au carré, puis additionnez, b**2 + c**2",
    "moments_full_matrix": "les trois moments remplissent toute la matrice 3×3 (diffusés sur les lignes ou les "
                           "colonnes) : ils vont sur la diagonale seulement, np.diag([I_xx, I_yy, I_zz]), des zéros "
                           "ailleurs",
    "xor_power": "`^` n'est pas une puissance en Python : c'est le XOR (ou exclusif bit à bit), que les flottants "
                 "n'ont pas — écrivez b**2 (ou b * b)",
    "factor_order": "les facteurs sont dans le mauvais ordre : I⁻¹(t) = R · I⁻¹_body · Rᵀ, R d'abord et Rᵀ à la fin "
                    "(un produit matriciel ne commute pas, et le R d'Euler n'est pas une rotation : R Rᵀ ≠ I)",
    "cross_for_product": "ω = I⁻¹(t) · L est une matrice fois un vecteur, I_inv @ L : np.cross est le produit "
                         "vectoriel ∧, qui n'a rien à faire ici",
    "elementwise_cross": "(rᵢ − x) ∧ Fᵢ est le produit vectoriel np.cross(r - x, F) : `*` (ou np.multiply, einsum "
                         "sans le ε) multiplie terme à terme",
    "int_in_place": "un tableau d'entiers ne peut pas recevoir un flottant sur place : np.array([0, 0, 0]) (ou "
                    "np.zeros(3, dtype=int)) contient des entiers, et `F += F_i` devrait tronquer, donc NumPy refuse ; "
                    "partez de flottants : np.zeros(3)",
    "state_attributes": "X.x marche sur le StateTuple des vérifications, mais simulate passe à votre fonction l'état "
                        "renvoyé par votre pas, un tuple ordinaire (x, R, P, L), qui n'a pas de .x : dépaquetez-le, "
                        "x, R, P, L = X",
    "tuple_arithmetic": "X est un tuple de quatre tableaux de formes différentes : un tuple fois un flottant lève une "
                        "erreur, `X + Y` met deux tuples bout à bout, np.array(X) ne peut pas contenir ensemble un (3,) "
                        "et un (3, 3) — mettez à jour chaque partie : x + dt * v, R + dt * R_dot, P + dt * F, "
                        "L + dt * tau",
    "other_method": "une autre méthode que l'Euler explicite des slides : X(t+Δt) = X(t) + Δt · dX/dt(t), avec "
                    "dX/dt évalué une seule fois, en X(t)",
    "call_order": "{detail} : l'appel de la boucle est X = step(M, I_body_inv, X, forces_at(t, X), dt) — "
                  "forces_at(t, X) prend le temps d'abord, step prend les forces avant dt",
    "states_transposed": "un état par ligne : x de forme (n_steps + 1, 3), R (n_steps + 1, 3, 3) ; les vôtres sont "
                         "transposés (.T, np.column_stack, np.stack(…, axis=-1)) — np.array(liste_des_x) empile les "
                         "états en lignes",
    "state_not_advanced": "X n'est jamais remplacé par le nouvel état : chaque pas doit partir du précédent, "
                          "X = step(M, I_body_inv, X, forces_at(t, X), dt) — le vôtre repart de X₀ à chaque pas",
    "scipy_negative_det": "Rotation.from_matrix de scipy refuse une matrice de det R < 0 (une ValueError) : ici "
                          "det(U Vᵀ) = −1 — utilisez la SVD, U, S, Vt = np.linalg.svd(R), et changez le signe de la "
                          "dernière colonne de U quand det(U @ Vt) < 0",
    "forces_changed": "step doit recevoir les forces que forces_at(t_k, X_k) a renvoyées à ce pas, telles quelles (pas "
                      "gardées des pas précédents, complétées ou modifiées) : X = step(M, I_body_inv, X, forces_at(t, X), "
                      "dt)",
    "stateful": "votre fonction répond d'après un appel précédent ({detail}) : un cache, une variable globale, un "
                "argument par défaut modifiable, ou un drapeau posé au premier appel ? Calculez la réponse à partir des "
                "arguments, à chaque appel",
    "float32": "votre tableau est en float32, qui ne garde qu'environ 7 chiffres : toutes les vérifications "
               "demandent du float64 (le type par défaut de NumPy, np.zeros(3), np.array([…], dtype=float)), juste à "
               "1e-7 près en relatif — pas de dtype=np.float32 ni de .astype(np.float32)",
    "parts_order": "les parties du résultat sont dans un autre ordre : {detail}",
    "column_vector": "une colonne (3, 1) là où un vecteur de forme (3,) est demandé : construisez les vecteurs avec "
                     "np.array([a, b, c]), pas [[a], [b], [c]] (ou aplatissez avec .ravel())",
}
