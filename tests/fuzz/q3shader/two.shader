textures/base/wall
{
	qer_editorimage textures/base/wall.tga
	cull none
	{
		map textures/base/wall.tga
		alphaFunc GE128
	}
}

textures/sky/s
{
	surfaceparm sky
	{
		animmap 5 a.tga b.tga
	}
}
